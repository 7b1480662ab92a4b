/* What the model tests share: settings from "key=value key=value" text,
 * steps that fail the test. */
#ifndef TB_TEST_MODELS_H
#define TB_TEST_MODELS_H

#include "models/tb_model.h"

/* The settings kvs lists (space separated; "" for the defaults); a bad
 * entry fails the calling test. Defined in tests/test_models.c. */
tb_settings tb_test_settings(const char *kvs);
/* n steps of in; a failing step fails the calling test (model, step, why)
 * and returns -1. Defined in tests/test_models.c. */
int tb_test_steps(tb_model *m, const tb_step *in, int n);

#endif
