/* placeholder */
#include <stddef.h>
#include "tb_test.h"
const tb_test_case tb_tests_msm_vvs[] = {{NULL, NULL}};
