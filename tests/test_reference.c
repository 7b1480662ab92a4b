/* Tests of the reference work (placeholder). */
#include "tb_test.h"

const tb_test_case tb_tests_reference[] = {
    {0, 0},
};
