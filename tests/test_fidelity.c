/* Tests of the fidelity work (placeholder). */
#include "tb_test.h"

const tb_test_case tb_tests_fidelity[] = {
    {0, 0},
};
