/*
 * rng: reproducible random numbers.
 *
 * Stochastic forces (Langevin, DPD) draw from a counter-based stream keyed
 * on (seed, call site, step, particle ids): the number a particle gets never
 * depends on thread count, rank count or loop order.  Sequential set-up
 * draws (initial velocities, displacements) use a seeded GSL generator.
 */
#ifndef CASCADE_RNG_H
#define CASCADE_RNG_H

#include <stdint.h>

/* Call sites: part of the key, so two uses at one step are independent. */
enum rng_site {
    RNG_SITE_LANGEVIN = 1,
    RNG_SITE_DPD_PAIR = 2,
    RNG_SITE_DPDE_PAIR = 3,
    RNG_SITE_MPM = 4,
};

static inline uint64_t rng_mix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ull;   /* SplitMix64 finaliser */
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* The key in two parts: the (seed, site, step) prefix is the same for every
 * draw of a step (a loop computes it once), the pair part (a, b) follows. */
static inline uint64_t rng_key_prefix(uint64_t seed, uint64_t site, uint64_t step)
{
    return rng_mix64(rng_mix64(seed ^ (site << 56)) ^ step);
}

static inline uint64_t rng_key_from(uint64_t prefix, uint64_t a, uint64_t b)
{
    uint64_t h = rng_mix64(prefix ^ a);
    return rng_mix64(h ^ (b * 0xd6e8feb86659fd93ull));
}

static inline uint64_t rng_key(uint64_t seed, uint64_t site, uint64_t step, uint64_t a, uint64_t b)
{
    return rng_key_from(rng_key_prefix(seed, site, step), a, b);
}

/* Uniform in (0, 1) from a key and a sub-index. */
static inline double rng_uniform(uint64_t key, uint64_t k)
{
    uint64_t z = rng_mix64(key + 0x632be59bd9b4e019ull * (k + 1));
    return ((double)(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/* Standard normal from a key and a sub-index (Box-Muller). */
double rng_gaussian(uint64_t key, uint64_t k);

/* Sequential generator for set-up (wraps gsl_rng mt19937). */
struct rng_seq;
struct rng_seq *rng_seq_create(uint64_t seed);
void rng_seq_destroy(struct rng_seq **r);
double rng_seq_uniform(struct rng_seq *r);
double rng_seq_gaussian(struct rng_seq *r);

#endif
