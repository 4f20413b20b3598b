/*
 * dpd_structure: the coarse-grained structure picture of Chen et al. 2014,
 * Fig. 4 -- common neighbour analysis (analysis/structure.h) of the DPD
 * particles at the coarse lattice constant: fcc, hcp, other.  Used by the
 * flyer/target case types (dpd_impact, dpd_grid_impact, dpd_mpm_impact).
 *
 *   analysis:
 *     structure:
 *       reference: fcc        fcc | hcp | bcc | diamond
 *       method: fixed         fixed | adaptive
 *       lattice_constant: 0   Å: 0 = the parameter file's coarse lattice constant
 *                             `a` (7.23 Å for Cu): fixed cutoff 0.5 (1 + 1/sqrt 2) a
 *       cutoff: 0             Å: 0 = from the lattice constant
 *       surface_offset: 0.15
 *
 * Every particle's class goes to the per-particle field `structure` (codes
 * of structure.h: 0 other12, 1 fcc, 2 hcp, 3 bcc, 4 ico, 5 not12, 6
 * surface), so it is in every HDF5 snapshot; the counts over the counted
 * particles (the target, not the flyer or the material points' partners)
 * at the start and the end of the run become metrics:
 *   cna_fcc, cna_hcp, cna_other (everything else, surface included, as in
 *   the paper's picture), cna_surface (part of cna_other), cna_fcc_start,
 *   cna_hcp_start, cna_fcc_fraction (of the counted particles at the end).
 */
#ifndef CASCADE_DPD_STRUCTURE_H
#define CASCADE_DPD_STRUCTURE_H

#include <stdint.h>

#include "analysis/frame.h"
#include "analysis/structure.h"
#include "dpd/dpd.h"
#include "output/checkpoint.h"
#include "output/run.h"
#include "util/cfg.h"

struct dpd_structure {
    struct structure_params sp;   /* resolved by dpd_structure_attach */
    struct frame fr;              /* scratch */
    int *cls;
    long cap;
    int field;                    /* particle field "structure" */
    uint32_t exclude;             /* mask bits of particles not counted */
    long counts[STRUCT_NCLASSES], start[STRUCT_NCLASSES], counted;
    long classified_step;         /* step of the last classification (-1: none) */
};

/* Read analysis.structure (created with defaults when absent). */
int dpd_structure_read(struct cfg_obj *root, struct dpd_structure *s);

/* Resolve the parameters (lattice constant 0: `a`, Å), add the particle
 * field to d's particles, count particles with none of the bits `exclude`. */
int dpd_structure_attach(struct dpd_structure *s, struct dpd *d, double a, uint32_t exclude,
                         int nthreads, struct err *e);

/* Classify d's owned particles into the field and the counts (the first
 * call, at the start of the run, also sets the start counts). */
int dpd_structure_classify(struct dpd_structure *s, struct dpd *d, struct err *e);

/* Classify when a snapshot is due at d->step and the classes are not yet
 * current (call before dpd_output_step). */
int dpd_structure_before_output(struct dpd_structure *s, struct run *run, struct dpd *d,
                                long total_steps, struct err *e);

/* Classify the final state (unless just done) and write the metrics. */
int dpd_structure_finish(struct dpd_structure *s, struct run *run, struct dpd *d, struct err *e);

/* The counts at the start and of the last classification, and its step,
 * for a restarted run (the classes themselves are the particle field,
 * checkpointed with the particles). */
int dpd_structure_checkpoint_write(const struct dpd_structure *s, struct ckpt *ck);
int dpd_structure_checkpoint_read(struct dpd_structure *s, struct ckpt *ck);

void dpd_structure_free(struct dpd_structure *s);

#endif
