/*
 * h5out: the run's HDF5 file and its XDMF sidecar.
 *
 * Layout (every dataset carries a "unit" attribute):
 *   /                         attributes: provenance, case (canonical JSON), units
 *   /particles/NNNNNNNN/      one group per snapshot (attributes step, time_ps):
 *        position (N x 3, Å), velocity (N x 3, Å/ps), force (N x 3, eV/Å),
 *        id, type, pe (eV), stress (N x 6: xx yy zz xy xz yz, GPa),
 *        and any extra per-particle fields (structure class, region, ...);
 *        cell/ (h5out_snapshot_cell): lo, hi (3, Å), tilt (xy xz yz, Å;
 *        0 0 0: orthogonal; the MD box's, core/box.h), pbc (3, 1 = periodic), attribute boundary
 *        (for example "periodic periodic free")
 *   /series/NAME              1-D time series (thermo columns)
 *   /points/NNNNNNNN/         MPM material points (a point cloud like /particles)
 *   /grid/NNNNNNNN/           MPM grid fields: on a uniform grid a structured
 *                             snapshot (h5out_begin_grid_snapshot) whose node
 *                             fields are (nz, ny, nx[, ncomp]) arrays; on other
 *                             grids a point cloud of the nodes
 *
 * Every N x 6 dataset (symmetric tensors) carries the attribute
 * components = "xx yy zz xy xz yz" (Voigt order).
 *
 * The XDMF file (same name, .xdmf) describes the snapshots as temporal
 * collections -- point clouds (Polyvertex) and structured grids
 * (3DCoRectMesh) -- so ParaView opens them directly.  A 6-component
 * (symmetric tensor) field is described as six scalars NAME_xx ... NAME_yz,
 * each a HyperSlab of its column, not as an XDMF Tensor6: that type's
 * component order is xx xy xz yy yz zz (ParaView expands it to the 3 x 3
 * tensor 0 1 2 / 1 3 4 / 2 4 5), not the Voigt order of the datasets, and
 * a scalar per component names each one without ambiguity.  The cells of
 * the snapshots that have one form a collection "cell" of box outlines
 * (12 edges, Polyline), in step with the particles.  Times and the root
 * "units" attribute are in metal units (ps) unless h5out_set_units says
 * otherwise (MPM cases written in SI).
 */
#ifndef CASCADE_H5OUT_H
#define CASCADE_H5OUT_H

#include <hdf5.h>
#include <jansson.h>
#include <stdint.h>

#include "util/err.h"

#define H5OUT_MAX_SNAPS 100000
#define H5OUT_MAX_FIELDS 32

struct h5out_field {
    char name[48];
    int ncomp;          /* 1, 3 or 6 (6 = symmetric tensor, written as 6 columns) */
    int is_int;         /* integer data */
    char unit[16];
};

/* One snapshot's description, kept to write the XDMF at the end. */
struct h5out_snap {
    char group[64];
    char collection[16];   /* "particles" or "grid" ... */
    long step;
    double time;
    long n;
    int structured;        /* 1: 3DCoRectMesh of dims nodes (origin, spacing) */
    long dims[3];          /* x, y, z node counts */
    double origin[3], spacing[3];
    int has_cell;          /* h5out_snapshot_cell was called */
    double cell_lo[3], cell_hi[3], cell_tilt[3];
    int nfields;
    struct h5out_field fields[H5OUT_MAX_FIELDS];
};

struct h5out {
    hid_t file;
    char path[4096];       /* the file's name; written as PATH.tmp until h5out_close */
    char tmp_path[4096 + 8];
    int failed;            /* a write failed: h5out_close removes PATH.tmp */
    char xdmf_path[4096];
    int nsnaps;
    struct h5out_snap *snaps;
    int cap_snaps;
    char time_unit[16];    /* unit of snapshot times ("ps" unless set) */
    /* A collective snapshot (h5out_par_begin .. h5out_par_end): every rank
     * holds the file open through MPI-IO; per-particle datasets take this
     * rank's rows [par_offset, par_offset + par_local) of par_total. */
    int par;
    int par_rank;
    long par_local, par_offset, par_total;
    /* ... and a structured snapshot's node fields this rank's block of
     * nodes par_glo[d] .. par_glo[d] + par_gn[d] - 1 (h5out_par_grid_block) */
    int par_grid;
    long par_glo[3], par_gn[3];
};

/* Create PATH.tmp; h5out_close renames it over PATH (and writes the XDMF
 * file), so a reader never finds a half-written fields.h5.  Fault points of
 * CASCADE_FAULT_WRITE (util/fault.h): the create, each dataset, the flush,
 * the fsync and the rename. */
int h5out_create(struct h5out *h, const char *path, const json_t *case_doc, struct err *e);
/* Close and remove PATH.tmp: the run ends without this file. */
void h5out_discard(struct h5out *h);
/* Begin a snapshot group; returns the group id or H5I_INVALID_HID. */
hid_t h5out_begin_snapshot(struct h5out *h, const char *collection, long step, double time, long n,
                           struct err *e);
int h5out_write_doubles(struct h5out *h, hid_t group, const char *name, const double *data, long n,
                        int ncomp, const char *unit, struct err *e);
int h5out_write_ints(struct h5out *h, hid_t group, const char *name, const int64_t *data, long n,
                     const char *unit, struct err *e);
void h5out_end_snapshot(struct h5out *h, hid_t group);

/* The simulation cell of the open snapshot `group`, in the convention of
 * LAMMPS: edge vectors a = (hi-lo)_x e_x, b = (xy, (hi-lo)_y, 0),
 * c = (xz, yz, (hi-lo)_z) from the corner lo; tilt may be NULL (orthogonal).
 * pbc[d] is 1 along periodic axes; boundary names the boundary kinds. */
int h5out_snapshot_cell(struct h5out *h, hid_t group, const double lo[3], const double hi[3],
                        const double tilt[3], const int pbc[3], const char *boundary,
                        struct err *e);

/* A structured snapshot of a uniform grid of dims[0] x dims[1] x dims[2]
 * nodes (x fastest) at origin with spacing; its node fields are written with
 * h5out_write_grid_doubles. */
hid_t h5out_begin_grid_snapshot(struct h5out *h, const char *collection, long step, double time,
                                const long dims[3], const double origin[3],
                                const double spacing[3], struct err *e);
/* A node field of the current structured snapshot: data holds
 * dims[0] dims[1] dims[2] x ncomp values, x fastest. */
int h5out_write_grid_doubles(struct h5out *h, hid_t group, const char *name, const double *data,
                             int ncomp, const char *unit, struct err *e);

/* Replace the file's "units" description and the unit of snapshot times
 * (attribute "time_<unit>" and the XDMF times), for runs whose outputs are
 * not in metal units. */
void h5out_set_units(struct h5out *h, const char *description, const char *time_unit);
/* A named 1-D series under /series. */
int h5out_write_series(struct h5out *h, const char *name, const double *data, long n,
                       const char *unit, struct err *e);
/* Write the XDMF sidecar and close the file. */
int h5out_close(struct h5out *h, struct err *e);

/* A collective particle snapshot of a brick decomposition (docs/parallel.md,
 * "Output").  Every rank calls h5out_par_begin with its count of owned
 * particles (rank 0 with its open h5out, the others with an h5out that
 * h5out_par_attach named), then the same sequence of
 * h5out_begin_snapshot / h5out_snapshot_cell / h5out_write_* /
 * h5out_end_snapshot with its own particles, then h5out_par_end.  Between
 * the two, rank 0's serial handle is closed and every rank holds the file
 * open through MPI-IO (H5Pset_fapl_mpio): each per-particle dataset has the
 * total count of rows and each rank writes its rows at the offset of an
 * MPI_Exscan of the counts, in one collective transfer (H5FD_MPIO_COLLECTIVE);
 * the cell and other small datasets are written by rank 0.  The datasets
 * have the serial file's type, shape, chunks and filters, in the order
 * rank 0's particles, rank 1's, ... (each rank's in its own order).  Every
 * failure (and every injected fault) is agreed over the ranks, so all
 * ranks return the same error at the same call and none waits in a
 * collective call another rank skipped.  Collective over MPI_COMM_WORLD. */
void h5out_par_attach(struct h5out *h, const char *path);
int h5out_par_begin(struct h5out *h, long n_local, struct err *e);
/* Inside a collective snapshot, after h5out_begin_grid_snapshot (the whole
 * grid's dims, origin and spacing on every rank): this rank's block of
 * nodes, lo[d] .. lo[d] + n[d] - 1 along x, y, z (n[d] may be 0).  Its
 * h5out_write_grid_doubles calls then take the block's values (x fastest)
 * and write them into the whole grid's datasets in one collective
 * transfer, so no rank holds the whole grid.  The blocks of the ranks
 * must not overlap.  Until h5out_end_snapshot. */
void h5out_par_grid_block(struct h5out *h, const long lo[3], const long n[3]);
/* rc: this rank's result since h5out_par_begin; returns it agreed over the
 * ranks; rank 0 has its serial handle back. */
int h5out_par_end(struct h5out *h, int rc, struct err *e);
/* rc agreed over the ranks inside a collective snapshot (rc itself outside
 * one): an error on any rank is an error on every rank. */
int h5out_par_agree(const struct h5out *h, int rc, struct err *e);

/* Attribute helpers. */
void h5out_attr_string(hid_t obj, const char *name, const char *value);
void h5out_attr_double(hid_t obj, const char *name, double value);

#endif
