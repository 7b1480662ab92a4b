/* What the model tests share: settings from "key=value key=value" text. */
#ifndef TB_TEST_MODELS_H
#define TB_TEST_MODELS_H

#include "tb_model.h"

/* The settings kvs lists (space separated; "" for the defaults); a bad
 * entry fails the calling test. Defined in tests/test_models.c. */
tb_settings tb_test_settings(const char *kvs);

#endif
