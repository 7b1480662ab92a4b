/* Tests of the stability work (placeholder). */
#include "tb_test.h"

const tb_test_case tb_tests_stability[] = {
    {0, 0},
};
