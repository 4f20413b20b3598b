/* rng: Box-Muller on the counter-based stream; GSL for sequential draws. */
#include "core/rng.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>

double rng_gaussian(uint64_t key, uint64_t k)
{
    double u1 = rng_uniform(key, 2 * k);
    double u2 = rng_uniform(key, 2 * k + 1);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}

struct rng_seq {
    gsl_rng *g;
};

struct rng_seq *rng_seq_create(uint64_t seed)
{
    struct rng_seq *r = malloc(sizeof *r);
    if (!r)
        return NULL;
    r->g = gsl_rng_alloc(gsl_rng_mt19937);
    if (!r->g) {
        free(r);
        return NULL;
    }
    gsl_rng_set(r->g, (unsigned long)rng_mix64(seed));
    return r;
}

void rng_seq_destroy(struct rng_seq **pr)
{
    if (!pr || !*pr)
        return;
    gsl_rng_free((*pr)->g);
    free(*pr);
    *pr = NULL;
}

double rng_seq_uniform(struct rng_seq *r) { return gsl_rng_uniform_pos(r->g); }
double rng_seq_gaussian(struct rng_seq *r) { return gsl_ran_gaussian_ziggurat(r->g, 1.0); }
