/*
 * th_case: running one case file through `cascade-solver run` and reading
 * the metrics of its result.json, for the tests that check a case type's
 * numbers end to end.
 */
#ifndef CASCADE_TEST_CASE_H
#define CASCADE_TEST_CASE_H

#include <jansson.h>

/* Write text to TEMP/name (th_write_temp's slot), run it into
 * TEMP/name-out (asserts that it ran) and return its result.json (the
 * caller owns it). */
json_t *th_run_case(int slot, const char *name, const char *text);

/* The value of the metric `name` in result.json's "metrics" object m
 * (asserts that it is there and a number). */
double th_metric_value(json_t *m, const char *name);

/* Run `type: elastic` (seed 5) with the crystal section `crystal`, the
 * potential section `potential` and the elastic section `elastic`, and
 * expect the values a case that computed them itself (thermal.from_potential)
 * reports in its metrics m: lattice_constant_T, c11_mpm, c12_mpm, c44_mpm
 * (to round-off), the errors c11_T_err... and thermal_expansion. */
void th_expect_type_elastic(int slot, const char *crystal, const char *potential,
                            const char *elastic, json_t *m);

#endif
