/*
 * th: helpers shared by the Criterion tests -- potentials from YAML
 * snippets, small crystals, finite-difference energies, running the
 * programs under test.
 */
#ifndef CASCADE_TEST_HELPERS_H
#define CASCADE_TEST_HELPERS_H

#include "core/box.h"
#include "core/lattice.h"
#include "core/particles.h"
#include "md/md.h"
#include "md/potential.h"

/* A potential from the YAML text of a `potential` section; aborts the test
 * with the error message on failure. */
struct potential *th_potential(const char *yaml);

/* Periodic crystal of n^3 cells, positions displaced uniformly by up to
 * `displace` Å with a fixed seed. */
struct particles *th_crystal(enum lattice_style style, double a, long n, const char *element,
                             double displace, unsigned seed, struct box *box);

/* An md over (p, box, pot) with 1 thread; md takes ownership of p and pot. */
void th_md(struct md *md, struct particles *p, const struct box *box, struct potential *pot,
           int nthreads);

/* Total potential energy at the current positions (recomputes forces). */
double th_energy(struct md *md);

/* Run a program with arguments; captures stdout+stderr into out (may be
 * NULL); returns the exit status (or 128 + signal). */
int th_run(const char *const *argv, char *out, size_t outlen);

/* Paths of the programs under test (from the environment set by make). */
const char *th_solver(void);
const char *th_root(void);

/* Write text to a new file in a fresh temporary directory; returns the
 * path (static storage per call slot 0..7). */
const char *th_write_temp(int slot, const char *name, const char *text);
const char *th_temp_dir(void);

#endif
