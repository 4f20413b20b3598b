/*
 * refine_run: a study with `refine:` (refine_spec.h) run until it
 * converges.  The runner runs the start levels (the sweep's values of the
 * axis), computes the Celik procedure per series -- per combination of the
 * other swept values -- and gives each series whose GCI (or band) is above
 * the tolerance, or whose ratio is outside the asymptotic range, its next
 * finer level (h / ratio; zipped keys follow as refine.follow says), until
 * every series has converged, reached max_levels, would break the budget,
 * or is found divergent or oscillatory (or a job of it failed).
 *
 * Each added level is an ordinary job with its key: the study is planned
 * with the axis's values extended by the added levels and the jobs a series
 * does not need dropped (study_run_opts.plan_filter), then registered and
 * run as `cascade run` does.  A rerun replays the same decisions from the
 * recorded results, so it resumes and never repeats a job that is done.
 *
 * The cost model: each series' next level is predicted from the measured
 * wall times of its two finest levels, t(h) = t1 (h1/h)^k with k = ln(t1/t2)
 * / ln(h2/h1) (clamped to 0..6), times its jobs and cores (threads x mpirun
 * ranks); a level whose prediction would take the study's core-seconds
 * (those of the jobs of the levels in use) past the budget is not started,
 * and the series is stopped saying so.  After every round the state of
 * each series goes to the refine_groups table (refine_state.h) and its
 * convergence rows to the convergence table.
 */
#ifndef CASCADE_CAMPAIGN_REFINE_RUN_H
#define CASCADE_CAMPAIGN_REFINE_RUN_H

#include <stdio.h>

#include "study_run.h"

int refine_run(const struct study *s, const struct study_run_opts *o, struct runner_summary *sum,
               FILE *log, struct err *e);

/* study_run, or refine_run when the study has a refine: section. */
int study_run_any(const struct study *s, const struct study_run_opts *o,
                  struct runner_summary *sum, struct err *e);

#endif
