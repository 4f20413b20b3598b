/*
 * md_analysis: structure analysis during an MD run -- local crystalline
 * order, displaced atoms, sputtered atoms and the crater -- written as
 * per-atom fields (so they appear in every HDF5 snapshot, colourable in
 * ParaView and OVITO) and as counts over time (result.json series and
 * /series in fields.h5).
 *
 * Per-atom fields (values are codes, unit "1"):
 *   structure   class code of analysis/structure.h (0 other12, 1 fcc, 2 hcp,
 *               3 bcc, 4 ico, 5 not12, 6 surface, 7 coord4, 8 not4)
 *   displaced   1 for a counted atom whose class is neither the ideal one
 *               nor surface (Guo & Yang 2005, section 3.2)
 *   sputtered   1 for an atom of a sputtered group (sputter.h)
 *   crater      1 for the top atom of a crater column (crater.h)
 *
 * Series (one value per analysis, time in ps from the start of the run):
 *   analysis_time_ps, n_<class> for every class, displaced, and with the
 *   sputter and crater analyses sputtered_atoms, sputtered_clusters,
 *   crater_depth_A, crater_volume_A3, crater_extent_100_A,
 *   crater_extent_110_A, rim_height_A; with the damage shape (damage_shape.h)
 *   of the displaced atoms below the surface: damage_atoms,
 *   damage_lmax_A2, damage_lmin_A2, damage_eig_ratio, damage_axis_deg,
 *   damage_extent_100_A, damage_extent_110_A, damage_extent_ratio (NaN,
 *   null in result.json, while fewer than three atoms are displaced).
 *
 * The case section:
 *   analysis:
 *     every: 100          steps between analyses (0: at snapshots only;
 *                         snapshots always carry current fields)
 *     structure: {reference, method, lattice_constant, cutoff, surface_offset}
 *                         (structure.h; defaults from the case's lattice)
 */
#ifndef CASCADE_MD_ANALYSIS_H
#define CASCADE_MD_ANALYSIS_H

#include <stdint.h>

#include "analysis/crater.h"
#include "analysis/damage_shape.h"
#include "analysis/frame.h"
#include "analysis/sputter.h"
#include "analysis/structure.h"
#include "core/box.h"
#include "core/particles.h"
#include "core/timers.h"
#include "output/run.h"

/* What the case asks for besides the structure classes. */
struct md_analysis_opts {
    uint32_t exclude_mask;     /* particles left out of the counts (boundary layers) */
    int sputter;               /* find sputtered groups (surface normal +z) */
    int crater;                /* measure the crater (surface normal +z) */
    double surface;            /* Å: original surface height */
    double center[2];          /* Å: impact point */
    double lat_lo[2], lat_hi[2];   /* Å: lateral extent for the crater grid */
    double crater_bin, crater_threshold;   /* Å */
    int damage_shape;          /* top-view shape of the displaced atoms more than
                                  crater_threshold below `surface` */
};

enum { MDA_MAXCOLS = 32 };

struct md_analysis {
    long every;
    struct structure_params sp;
    struct md_analysis_opts o;
    struct frame fr;
    int *cls;
    unsigned char *sel, *sput, *floor_atom, *damaged;
    double *mass, *shape_scratch;
    int cap;
    int f_structure, f_displaced, f_sputtered, f_crater;
    int ncols;
    const char *cols[MDA_MAXCOLS];
    const char *units[MDA_MAXCOLS];
    double *rows;
    long nrows, caprows;
    /* latest results */
    long counts[STRUCT_NCLASSES], displaced, counted;
    struct sputter_stats sputter;
    struct crater_stats crater;
    struct damage_shape shape;
};

/* Read the `analysis` section (always present in the resolved case);
 * `def` gives the structure defaults from the case's lattice. */
int md_analysis_read(struct cfg_obj *root, const struct structure_params *def, long def_every,
                     struct md_analysis *a);

/* Register the per-atom fields on the particle set and fix the columns. */
int md_analysis_attach(struct md_analysis *a, struct particles *p,
                       const struct md_analysis_opts *o, int nthreads, struct err *e);

/* Whether step s of `total` is an analysis step (snapshot steps included). */
int md_analysis_due(const struct md_analysis *a, const struct run *run, long s, long total);

/* Analyse the current configuration (owned particles of p in box at
 * `time` ps), fill the fields, append a row; timed as TIMER_ANALYSIS when
 * timers is not NULL. */
int md_analysis_run(struct md_analysis *a, struct particles *p, const struct box *box, double time,
                    struct timers *timers, struct err *e);

/* The parts of md_analysis_run the brick analysis (md_analysis_bricks.h)
 * shares.  Room for n particles in the scratch arrays: */
int md_analysis_reserve(struct md_analysis *a, int n, struct err *e);
/* From a->cls of p's owned particles: sel, mass, the class counts,
 * displaced and damaged, the structure and displaced fields. */
void md_analysis_mark(struct md_analysis *a, struct particles *p);
/* The sputter and crater parameters of the case. */
struct sputter_params md_analysis_sputter_params(const struct md_analysis *a);
struct crater_params md_analysis_crater_params(const struct md_analysis *a);
/* Append the row of the latest results (counts, sputter, crater, shape). */
int md_analysis_push_latest(struct md_analysis *a, double time, struct err *e);

/* Append one row of a->ncols values (a row another rank computed). */
int md_analysis_push_row(struct md_analysis *a, const double *row, struct err *e);

/* Free the per-particle scratch and the frame (rebuilt by the next run):
 * a rank that analysed every atom of a brick run gives the memory back. */
void md_analysis_release(struct md_analysis *a);

/* Series into result.json and fields.h5. */
int md_analysis_finish(struct md_analysis *a, struct run *run, struct err *e);

/* Column values of the stored rows: returns a pointer to row r. */
static inline const double *md_analysis_row(const struct md_analysis *a, long r)
{
    return a->rows + r * a->ncols;
}
int md_analysis_column(const struct md_analysis *a, const char *name);

void md_analysis_free(struct md_analysis *a);

#endif
