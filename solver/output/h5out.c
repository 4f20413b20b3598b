/* h5out: HDF5 snapshots and the XDMF sidecar for ParaView. */
#include "output/h5out.h"

#include <errno.h>
#include <hdf5_hl.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output/provenance.h"
#include "util/canon.h"
#include "util/fault.h"
#include "util/mem.h"
#include "util/wfile.h"

/* H5LT makes the same scalar string attribute (C string, NUL-terminated,
 * its length + 1) that h5out wrote by hand before. */
void h5out_attr_string(hid_t obj, const char *name, const char *value)
{
    H5LTset_attribute_string(obj, ".", name, value);
}

/* Not H5LTset_attribute_double: that one makes a 1-element array, and the
 * attributes of a snapshot (step, time) are scalars readers rely on. */
void h5out_attr_double(hid_t obj, const char *name, double value)
{
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t attr = H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(attr, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(attr);
    H5Sclose(space);
}

/* Whether flag is set on any rank (inside a collective snapshot; the flag
 * itself outside one). */
static int par_any(const struct h5out *h, int flag)
{
    if (!h->par)
        return flag != 0;
    int in = flag != 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return out;
}

int h5out_par_agree(const struct h5out *h, int rc, struct err *e)
{
    if (par_any(h, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME,
                               "cannot write %s: stopped: another MPI rank failed to write it",
                               h->path);
    return rc;
}

void h5out_par_attach(struct h5out *h, const char *path)
{
    memset(h, 0, sizeof *h);
    h->file = H5I_INVALID_HID;
    snprintf(h->time_unit, sizeof h->time_unit, "ps");
    snprintf(h->path, sizeof h->path, "%s", path);
    snprintf(h->tmp_path, sizeof h->tmp_path, "%s.tmp", path);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);   /* errors are reported by us */
}

int h5out_par_begin(struct h5out *h, long n_local, struct err *e)
{
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    /* the attribute names of the snapshot times follow rank 0's units */
    MPI_Bcast(h->time_unit, (int)sizeof h->time_unit, MPI_CHAR, 0, MPI_COMM_WORLD);
    long off = 0, tot = 0;
    MPI_Exscan(&n_local, &off, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(&n_local, &tot, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    h->par = 1;
    h->par_grid = 0;
    h->par_rank = rank;
    h->par_local = n_local;
    h->par_offset = rank == 0 ? 0 : off;   /* MPI_Exscan leaves rank 0's undefined */
    h->par_total = tot;
    int rc = 0;
    /* rank 0's serial handle closes (flushed) before the file opens again
     * through MPI-IO on every rank */
    if (rank == 0 && (h->file < 0 || H5Fclose(h->file) < 0))
        rc = err_set(e, ERR_RUNTIME, "cannot write %s: closing the serial HDF5 handle failed",
                     h->path);
    h->file = H5I_INVALID_HID;
    if (!rc && fault_write(ENOSPC) != 0)
        rc = err_set(e, ERR_RUNTIME, "cannot write %s: %s", h->path, strerror(errno));
    if (!(rc = h5out_par_agree(h, rc, e))) {
        hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
        H5Pset_fapl_mpio(fapl, MPI_COMM_WORLD, MPI_INFO_NULL);
        h->file = H5Fopen(h->tmp_path, H5F_ACC_RDWR, fapl);
        H5Pclose(fapl);
        if (h->file < 0)
            rc = err_set(e, ERR_RUNTIME, "cannot write %s: cannot open %s through MPI-IO",
                         h->path, h->tmp_path);
        rc = h5out_par_agree(h, rc, e);
    }
    if (rc)
        h->failed = 1;
    return rc;
}

int h5out_par_end(struct h5out *h, int rc, struct err *e)
{
    if (!h->par)
        return rc;
    if (h->file >= 0 && H5Fclose(h->file) < 0 && !rc)   /* collective */
        rc = err_set(e, ERR_RUNTIME, "cannot write %s: closing the HDF5 file failed", h->path);
    h->file = H5I_INVALID_HID;
    rc = h5out_par_agree(h, rc, e);
    h->par = 0;
    if (rc)
        h->failed = 1;   /* h5out_close / h5out_discard remove PATH.tmp */
    if (h->par_rank != 0) {   /* the others keep no snapshot index */
        free(h->snaps);
        h->snaps = NULL;
        h->nsnaps = h->cap_snaps = 0;
    } else if (!h->failed) {
        h->file = H5Fopen(h->tmp_path, H5F_ACC_RDWR, H5P_DEFAULT);
        if (h->file < 0) {
            h->failed = 1;
            rc = err_set(e, ERR_RUNTIME, "cannot write %s: cannot open %s again", h->path,
                         h->tmp_path);
        }
    }
    return rc;
}

int h5out_create(struct h5out *h, const char *path, const json_t *case_doc, struct err *e)
{
    memset(h, 0, sizeof *h);
    snprintf(h->time_unit, sizeof h->time_unit, "ps");
    snprintf(h->path, sizeof h->path, "%s", path);
    snprintf(h->xdmf_path, sizeof h->xdmf_path, "%s", path);
    char *dot = strrchr(h->xdmf_path, '.');
    if (dot)
        *dot = '\0';
    strncat(h->xdmf_path, ".xdmf", sizeof h->xdmf_path - strlen(h->xdmf_path) - 1);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);   /* errors are reported by us */
    h->file = H5I_INVALID_HID;
    if (snprintf(h->tmp_path, sizeof h->tmp_path, "%s.tmp", path) >= (int)sizeof h->tmp_path)
        return err_set(e, ERR_RUNTIME, "cannot write %s: the name is too long", path);
    if (fault_write(ENOSPC) != 0)
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", path, strerror(errno));
    h->file = H5Fcreate(h->tmp_path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (h->file < 0)
        return err_set(e, ERR_RUNTIME, "cannot write %s: cannot create the HDF5 file %s", path,
                       h->tmp_path);
    json_t *prov = provenance_json();
    char *ptext = canon_json(prov);
    json_decref(prov);
    char *ctext = case_doc ? canon_json(case_doc) : NULL;
    if (!ptext || (case_doc && !ctext)) {
        free(ptext);
        free(ctext);
        h5out_discard(h);
        return err_set(e, ERR_RUNTIME, "cannot write %s: out of memory (provenance)", path);
    }
    h5out_attr_string(h->file, "provenance", ptext);
    free(ptext);
    if (ctext)
        h5out_attr_string(h->file, "case", ctext);
    free(ctext);
    h5out_attr_string(h->file, "units",
                      "length: Å, time: ps, energy: eV, mass: amu, temperature: K, "
                      "velocity: Å/ps, force: eV/Å, stress: GPa");
    hid_t g = H5Gcreate2(h->file, "/particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Gclose(g);
    g = H5Gcreate2(h->file, "/series", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Gclose(g);
    return 0;
}

hid_t h5out_begin_snapshot(struct h5out *h, const char *collection, long step, double time, long n,
                           struct err *e)
{
    int grow = 0;
    if (h->nsnaps >= h->cap_snaps) {
        int cap = h->cap_snaps ? 2 * h->cap_snaps : 16;
        struct h5out_snap *s = mem_realloc(h->snaps, (size_t)cap * sizeof *s);
        if (s) {
            h->snaps = s;
            h->cap_snaps = cap;
        }
        grow = s ? 0 : err_nomem(e, "snapshot index");
    }
    if (h5out_par_agree(h, grow, e) != 0)   /* collective: every rank stops here */
        return H5I_INVALID_HID;
    struct h5out_snap *s = &h->snaps[h->nsnaps];
    memset(s, 0, sizeof *s);
    snprintf(s->collection, sizeof s->collection, "%s", collection);
    snprintf(s->group, sizeof s->group, "/%s/%08ld", collection, step);
    s->step = step;
    s->time = time;
    s->n = h->par ? h->par_total : n;   /* collective: the rows of every rank */
    char parent[64];
    snprintf(parent, sizeof parent, "/%s", collection);
    if (H5Lexists(h->file, parent, H5P_DEFAULT) <= 0) {
        hid_t pg = H5Gcreate2(h->file, parent, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        H5Gclose(pg);
    }
    if (H5Lexists(h->file, s->group, H5P_DEFAULT) > 0) {
        err_set(e, ERR_RUNTIME, "%s: snapshot %s written twice", h->path, s->group);
        return H5I_INVALID_HID;
    }
    hid_t g = H5Gcreate2(h->file, s->group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (par_any(h, g < 0)) {
        if (g >= 0)
            H5Gclose(g);
        h->failed = 1;
        err_set(e, ERR_RUNTIME, "cannot write %s: cannot create group %s", h->path, s->group);
        return H5I_INVALID_HID;
    }
    char tname[32];
    snprintf(tname, sizeof tname, "time_%s", h->time_unit);
    h5out_attr_double(g, tname, time);
    h5out_attr_double(g, "step", (double)step);
    h->nsnaps++;
    return g;
}

hid_t h5out_begin_grid_snapshot(struct h5out *h, const char *collection, long step, double time,
                                const long dims[3], const double origin[3],
                                const double spacing[3], struct err *e)
{
    long n = dims[0] * dims[1] * dims[2];
    hid_t g = h5out_begin_snapshot(h, collection, step, time, n, e);
    if (g < 0)
        return g;
    struct h5out_snap *s = &h->snaps[h->nsnaps - 1];
    s->structured = 1;
    for (int d = 0; d < 3; d++) {
        s->dims[d] = dims[d];
        s->origin[d] = origin[d];
        s->spacing[d] = spacing[d];
    }
    return g;
}

void h5out_set_units(struct h5out *h, const char *description, const char *time_unit)
{
    if (h->file >= 0) {
        if (H5Aexists(h->file, "units") > 0)
            H5Adelete(h->file, "units");
        h5out_attr_string(h->file, "units", description);
    }
    snprintf(h->time_unit, sizeof h->time_unit, "%s", time_unit);
}

/* Shape of a dataset: rank and dimensions (n x ncomp, or nz x ny x nx x ncomp). */
struct shape {
    int rank;
    hsize_t dims[4];
};

/* The collective transfer of one dataset: a per-particle dataset (dist)
 * takes this rank's rows at its offset, a structured snapshot's node
 * field (dist, h->par_grid) this rank's block of nodes, any other is
 * written by rank 0 (the others select nothing but take part). */
static herr_t par_write(const struct h5out *h, hid_t ds, hid_t memtype, const struct shape *full,
                        int dist, const void *data)
{
    hsize_t start[4] = {0, 0, 0, 0}, count[4], one[4] = {1, 1, 1, 1};
    for (int k = 0; k < full->rank; k++)
        count[k] = full->dims[k];
    int mine = h->par_rank == 0;
    if (dist && h->par_grid) {   /* dims are z, y, x (, components) */
        mine = 1;
        for (int d = 0; d < 3; d++) {
            start[2 - d] = (hsize_t)h->par_glo[d];
            count[2 - d] = (hsize_t)h->par_gn[d];
            mine &= h->par_gn[d] > 0;
        }
    } else if (dist) {
        start[0] = (hsize_t)h->par_offset;
        count[0] = (hsize_t)h->par_local;
        mine = h->par_local > 0;
    }
    static const double nothing = 0;   /* a buffer for a rank that writes nothing */
    hid_t fs = H5Dget_space(ds);
    hid_t ms = H5Screate_simple(full->rank, mine ? count : one, NULL);
    herr_t st = fs < 0 || ms < 0 ? -1 : 0;
    if (!st && mine)
        st = H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
    else if (!st)
        st = H5Sselect_none(fs) < 0 || H5Sselect_none(ms) < 0 ? -1 : 0;
    hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
    H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);   /* filtered datasets need it */
    /* every rank joins the transfer, also one whose selection failed */
    herr_t wst = H5Dwrite(ds, memtype, ms, fs, dxpl, mine ? data : &nothing);
    H5Pclose(dxpl);
    if (ms >= 0)
        H5Sclose(ms);
    if (fs >= 0)
        H5Sclose(fs);
    return st < 0 || wst < 0 ? -1 : 0;
}

void h5out_par_grid_block(struct h5out *h, const long lo[3], const long n[3])
{
    h->par_grid = 1;
    for (int d = 0; d < 3; d++) {
        h->par_glo[d] = lo[d];
        h->par_gn[d] = n[d];
    }
}

/* Writes one dataset with its unit (and, with 6 columns, the component
 * order); `record` lists it as a field of the open snapshot for the XDMF.
 * Small datasets (no chunks) of a serial write go through H5LT; chunked
 * ones and collective writes need the property lists of the low-level
 * API.  In a collective snapshot (h->par) a recorded dataset is
 * per-particle: n is this rank's rows, the dataset has par_total. */
static int write_dataset_shaped(struct h5out *h, hid_t group, const char *name, hid_t memtype,
                                const void *data, long n, int ncomp, const struct shape *sh,
                                const char *unit, int is_int, int record, struct err *e)
{
    int dist = h->par && record;
    struct shape full = *sh;
    if (dist && !h->par_grid) {   /* a grid block's dataset has the grid's shape */
        full.dims[0] = (hsize_t)h->par_total;
        n = h->par_total;
    }
    int chunked = n > 4096;
    int injected = par_any(h, fault_write(ENOSPC) != 0);
    herr_t st = 0;
    hid_t ds = H5I_INVALID_HID;
    if (injected) {
        st = -1;
    } else if (!chunked && !h->par) {
        st = H5LTmake_dataset(group, name, full.rank, full.dims, memtype, n > 0 ? data : NULL);
        if (st >= 0)
            H5LTset_attribute_string(group, name, "unit", unit);
        if (st >= 0 && ncomp == 6)
            H5LTset_attribute_string(group, name, "components", "xx yy zz xy xz yz");
    } else {
        hid_t space = H5Screate_simple(full.rank, full.dims, NULL);
        hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
        if (chunked) {   /* compress larger datasets */
            hsize_t chunk[4];
            for (int k = 0; k < full.rank; k++)
                chunk[k] = full.dims[k];
            /* about 64k elements per chunk along the slowest dimension */
            hsize_t per = (hsize_t)n / full.dims[0];
            hsize_t rows = per > 0 ? 65536 / per : 1;
            chunk[0] = rows < 1 ? 1 : rows > full.dims[0] ? full.dims[0] : rows;
            H5Pset_chunk(dcpl, full.rank, chunk);
            H5Pset_shuffle(dcpl);
            H5Pset_deflate(dcpl, 1);
        }
        ds = H5Dcreate2(group, name, memtype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
        H5Pclose(dcpl);
        H5Sclose(space);
        int created = !par_any(h, ds < 0);   /* on every rank, or it is not used */
        if (!created)
            st = -1;
        else if (h->par)
            st = n > 0 ? par_write(h, ds, memtype, &full, dist, data) : 0;
        else
            st = n > 0 ? H5Dwrite(ds, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
        if (created)
            h5out_attr_string(ds, "unit", unit);
        if (created && ncomp == 6)
            h5out_attr_string(ds, "components", "xx yy zz xy xz yz");
        if (ds >= 0)
            H5Dclose(ds);
    }
    if (par_any(h, st < 0)) {
        h->failed = 1;
        return err_set(e, ERR_RUNTIME, "cannot write %s: dataset %s%s", h->path, name,
                       injected ? ": No space left on device" : "");
    }
    if (record && h->nsnaps > 0) {
        struct h5out_snap *s = &h->snaps[h->nsnaps - 1];
        if (s->nfields < H5OUT_MAX_FIELDS) {
            struct h5out_field *f = &s->fields[s->nfields++];
            snprintf(f->name, sizeof f->name, "%s", name);
            f->ncomp = ncomp;
            f->is_int = is_int;
            snprintf(f->unit, sizeof f->unit, "%s", unit);
        }
    }
    return 0;
}

static int write_dataset(struct h5out *h, hid_t group, const char *name, hid_t memtype,
                         const void *data, long n, int ncomp, const char *unit, int is_int,
                         int record, struct err *e)
{
    struct shape sh = {ncomp > 1 ? 2 : 1, {(hsize_t)n, (hsize_t)ncomp, 0, 0}};
    return write_dataset_shaped(h, group, name, memtype, data, n, ncomp, &sh, unit, is_int,
                                record, e);
}

int h5out_write_grid_doubles(struct h5out *h, hid_t group, const char *name, const double *data,
                             int ncomp, const char *unit, struct err *e)
{
    if (h->nsnaps == 0 || !h->snaps[h->nsnaps - 1].structured)
        return err_set(e, ERR_RUNTIME, "%s: %s: no structured snapshot open", h->path, name);
    const struct h5out_snap *s = &h->snaps[h->nsnaps - 1];
    struct shape sh = {ncomp > 1 ? 4 : 3,
                       {(hsize_t)s->dims[2], (hsize_t)s->dims[1], (hsize_t)s->dims[0],
                        (hsize_t)ncomp}};
    return write_dataset_shaped(h, group, name, H5T_NATIVE_DOUBLE, data, s->n, ncomp, &sh, unit,
                                0, 1, e);
}

int h5out_write_doubles(struct h5out *h, hid_t group, const char *name, const double *data, long n,
                        int ncomp, const char *unit, struct err *e)
{
    return write_dataset(h, group, name, H5T_NATIVE_DOUBLE, data, n, ncomp, unit, 0, 1, e);
}

int h5out_write_ints(struct h5out *h, hid_t group, const char *name, const int64_t *data, long n,
                     const char *unit, struct err *e)
{
    return write_dataset(h, group, name, H5T_NATIVE_INT64, data, n, 1, unit, 1, 1, e);
}

int h5out_snapshot_cell(struct h5out *h, hid_t group, const double lo[3], const double hi[3],
                        const double tilt[3], const int pbc[3], const char *boundary,
                        struct err *e)
{
    if (h->nsnaps == 0)
        return err_set(e, ERR_RUNTIME, "%s: cell without a snapshot", h->path);
    struct h5out_snap *s = &h->snaps[h->nsnaps - 1];
    static const double zero[3] = {0, 0, 0};
    const double *t = tilt ? tilt : zero;
    hid_t g = H5Gcreate2(group, "cell", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (par_any(h, g < 0)) {
        if (g >= 0)
            H5Gclose(g);
        h->failed = 1;
        return err_set(e, ERR_RUNTIME, "cannot write %s: cannot create %s/cell", h->path,
                       s->group);
    }
    int64_t per[3] = {pbc[0] != 0, pbc[1] != 0, pbc[2] != 0};
    int rc = write_dataset(h, g, "lo", H5T_NATIVE_DOUBLE, lo, 3, 1, "Å", 0, 0, e);
    if (!rc)
        rc = write_dataset(h, g, "hi", H5T_NATIVE_DOUBLE, hi, 3, 1, "Å", 0, 0, e);
    if (!rc)
        rc = write_dataset(h, g, "tilt", H5T_NATIVE_DOUBLE, t, 3, 1, "Å", 0, 0, e);
    if (!rc)
        rc = write_dataset(h, g, "pbc", H5T_NATIVE_INT64, per, 3, 1, "1", 1, 0, e);
    if (!rc) {
        h5out_attr_string(g, "boundary", boundary ? boundary : "");
        h5out_attr_string(g, "convention",
                          "LAMMPS: edges a = (hi-lo)_x e_x, b = (xy, (hi-lo)_y, 0), "
                          "c = (xz, yz, (hi-lo)_z) from lo; tilt = xy xz yz; pbc 1 = periodic");
    }
    H5Gclose(g);
    if (rc)
        return rc;
    s->has_cell = 1;
    for (int d = 0; d < 3; d++) {
        s->cell_lo[d] = lo[d];
        s->cell_hi[d] = hi[d];
        s->cell_tilt[d] = t[d];
    }
    return 0;
}

void h5out_end_snapshot(struct h5out *h, hid_t group)
{
    h->par_grid = 0;
    if (group >= 0)
        H5Gclose(group);
}

int h5out_write_series(struct h5out *h, const char *name, const double *data, long n,
                       const char *unit, struct err *e)
{
    hid_t g = H5Gopen2(h->file, "/series", H5P_DEFAULT);
    if (g < 0)
        return err_set(e, ERR_RUNTIME, "%s: no /series group", h->path);
    /* series are not snapshot fields */
    int rc = write_dataset(h, g, name, H5T_NATIVE_DOUBLE, data, n, 1, unit, 0, 0, e);
    H5Gclose(g);
    return rc;
}

static const char *basename_of(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

/* Dimensions of a snapshot's field: node or point counts (z y x for
 * structured grids), then the components unless there is one; with
 * `last` >= 0 the components are replaced by `last`. */
static void xdmf_dims(const struct h5out_snap *s, int ncomp, int last, char *out, size_t len)
{
    int nc = last >= 0 ? last : ncomp;
    if (s->structured && nc == 1 && last < 0)
        snprintf(out, len, "%ld %ld %ld", s->dims[2], s->dims[1], s->dims[0]);
    else if (s->structured)
        snprintf(out, len, "%ld %ld %ld %d", s->dims[2], s->dims[1], s->dims[0], nc);
    else if (nc == 1 && last < 0)
        snprintf(out, len, "%ld", s->n);
    else
        snprintf(out, len, "%ld %d", s->n, nc);
}

static void write_xdmf_attribute(FILE *f, const char *h5name, const struct h5out_snap *s,
                                 const struct h5out_field *fl)
{
    const char *atype = fl->ncomp == 1 ? "Scalar" : fl->ncomp == 3 ? "Vector"
                        : fl->ncomp == 9 ? "Tensor" : "Matrix";
    char dims[96];
    xdmf_dims(s, fl->ncomp, -1, dims, sizeof dims);
    fprintf(f, "    <Attribute Name=\"%s [%s]\" AttributeType=\"%s\" Center=\"Node\">\n"
               "     <DataItem Dimensions=\"%s\" NumberType=\"%s\" Precision=\"8\" "
               "Format=\"HDF\">%s:%s/%s</DataItem>\n    </Attribute>\n",
            fl->name, fl->unit, atype, dims, fl->is_int ? "Int" : "Float", h5name, s->group,
            fl->name);
}

/* A symmetric tensor stored in Voigt order (xx yy zz xy xz yz) as six
 * scalars NAME_xx ... NAME_yz, each the HyperSlab of its column (start,
 * stride, count per dimension of the dataset). */
static void write_xdmf_tensor6(FILE *f, const char *h5name, const struct h5out_snap *s,
                               const struct h5out_field *fl)
{
    static const char *const comp[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
    char full[96], one[96];
    xdmf_dims(s, 6, -1, full, sizeof full);
    xdmf_dims(s, 6, 1, one, sizeof one);
    int rank = s->structured ? 4 : 2;
    for (int c = 0; c < 6; c++) {
        fprintf(f, "    <Attribute Name=\"%s_%s [%s]\" AttributeType=\"Scalar\" "
                   "Center=\"Node\">\n"
                   "     <DataItem ItemType=\"HyperSlab\" Dimensions=\"%s\" "
                   "Type=\"HyperSlab\">\n"
                   "      <DataItem Dimensions=\"3 %d\" Format=\"XML\">",
                fl->name, comp[c], fl->unit, one, rank);
        for (int k = 0; k < rank - 1; k++)
            fprintf(f, "0 ");
        fprintf(f, "%d ", c);
        for (int k = 0; k < rank; k++)
            fprintf(f, "1 ");
        fprintf(f, "%s</DataItem>\n", one);   /* count */
        fprintf(f, "      <DataItem Dimensions=\"%s\" NumberType=\"Float\" Precision=\"8\" "
                   "Format=\"HDF\">%s:%s/%s</DataItem>\n     </DataItem>\n    </Attribute>\n",
                full, h5name, s->group, fl->name);
    }
}

/* The cell of a snapshot as its 12 edges (a Polyline grid of 8 corners):
 * ParaView draws the box outline in step with the particles. */
static void write_xdmf_cell(FILE *f, const struct h5out_snap *s)
{
    const double *lo = s->cell_lo, *hi = s->cell_hi, *t = s->cell_tilt;
    double a[3] = {hi[0] - lo[0], 0, 0}, b[3] = {t[0], hi[1] - lo[1], 0},
           c[3] = {t[1], t[2], hi[2] - lo[2]};
    fprintf(f, "   <Grid Name=\"cell_%ld\" GridType=\"Uniform\">\n", s->step);
    fprintf(f, "    <Time Value=\"%.10g\"/>\n", s->time);
    /* corner k = lo + (k&1) a + (k>>1&1) b + (k>>2&1) c; the edges join
     * corners that differ in one bit */
    fprintf(f, "    <Topology TopologyType=\"Polyline\" NumberOfElements=\"12\" "
               "NodesPerElement=\"2\">\n     <DataItem Dimensions=\"12 2\" NumberType=\"Int\" "
               "Format=\"XML\">0 1 2 3 4 5 6 7 0 2 1 3 4 6 5 7 0 4 1 5 2 6 3 7</DataItem>\n"
               "    </Topology>\n");
    fprintf(f, "    <Geometry GeometryType=\"XYZ\">\n     <DataItem Dimensions=\"8 3\" "
               "NumberType=\"Float\" Precision=\"8\" Format=\"XML\">");
    for (int k = 0; k < 8; k++)
        for (int d = 0; d < 3; d++)
            fprintf(f, "%s%.17g", k || d ? " " : "",
                    lo[d] + (k & 1) * a[d] + (k >> 1 & 1) * b[d] + (k >> 2 & 1) * c[d]);
    fprintf(f, "</DataItem>\n    </Geometry>\n   </Grid>\n");
}

static int write_xdmf(const struct h5out *h, struct err *e)
{
    struct wfile w;
    int rc = wfile_open(&w, h->xdmf_path, e);
    if (rc)
        return rc;
    FILE *f = w.f;
    const char *h5name = basename_of(h->path);
    fprintf(f, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n");
    fprintf(f, "<!-- written by cascade-solver %s (git %s) -->\n", provenance_version(),
            provenance_git_hash());
    fprintf(f, "<Xdmf Version=\"3.0\">\n <Domain>\n");
    const char *collections[] = {"particles", "points", "grid"};
    for (int c = 0; c < 3; c++) {
        int any = 0;
        for (int k = 0; k < h->nsnaps; k++)
            any |= strcmp(h->snaps[k].collection, collections[c]) == 0;
        if (!any)
            continue;
        fprintf(f, "  <Grid Name=\"%s\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
                collections[c]);
        for (int k = 0; k < h->nsnaps; k++) {
            const struct h5out_snap *s = &h->snaps[k];
            if (strcmp(s->collection, collections[c]) != 0)
                continue;
            const char *geo = s->structured ? "" : "position";
            fprintf(f, "   <Grid Name=\"%s_%ld\" GridType=\"Uniform\">\n", collections[c], s->step);
            fprintf(f, "    <Time Value=\"%.10g\"/>\n", s->time);
            if (s->structured) {
                /* XDMF orders structured dimensions, origin and spacing z, y, x */
                fprintf(f, "    <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"%ld %ld %ld\"/>\n",
                        s->dims[2], s->dims[1], s->dims[0]);
                fprintf(f, "    <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
                           "     <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
                           "Format=\"XML\">%.17g %.17g %.17g</DataItem>\n"
                           "     <DataItem Dimensions=\"3\" NumberType=\"Float\" Precision=\"8\" "
                           "Format=\"XML\">%.17g %.17g %.17g</DataItem>\n    </Geometry>\n",
                        s->origin[2], s->origin[1], s->origin[0], s->spacing[2], s->spacing[1],
                        s->spacing[0]);
            } else {
                fprintf(f, "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%ld\" "
                           "NodesPerElement=\"1\"/>\n",
                        s->n);
                fprintf(f, "    <Geometry GeometryType=\"XYZ\">\n     <DataItem Dimensions=\"%ld 3\" "
                           "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:%s/%s</DataItem>\n"
                           "    </Geometry>\n",
                        s->n, h5name, s->group, geo);
            }
            for (int a = 0; a < s->nfields; a++) {
                const struct h5out_field *fl = &s->fields[a];
                if (strcmp(fl->name, geo) == 0)
                    continue;
                if (fl->ncomp == 6)
                    write_xdmf_tensor6(f, h5name, s, fl);
                else
                    write_xdmf_attribute(f, h5name, s, fl);
            }
            fprintf(f, "   </Grid>\n");
        }
        fprintf(f, "  </Grid>\n");
    }
    int ncells = 0;
    for (int k = 0; k < h->nsnaps; k++)
        ncells += h->snaps[k].has_cell;
    if (ncells > 0) {
        fprintf(f, "  <Grid Name=\"cell\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
        for (int k = 0; k < h->nsnaps; k++)
            if (h->snaps[k].has_cell)
                write_xdmf_cell(f, &h->snaps[k]);
        fprintf(f, "  </Grid>\n");
    }
    fprintf(f, " </Domain>\n</Xdmf>\n");
    return wfile_commit(&w, e);
}

/* Flush and fsync the open file (the sec2 driver's descriptor). */
static int flush_file(struct h5out *h, struct err *e)
{
    if (fault_write(ENOSPC) != 0 || H5Fflush(h->file, H5F_SCOPE_GLOBAL) < 0)
        return err_set(e, ERR_RUNTIME, "cannot write %s: %s", h->path,
                       errno ? strerror(errno) : "flushing the HDF5 file failed");
    void *handle = NULL;
    if (H5Fget_vfd_handle(h->file, H5P_DEFAULT, &handle) >= 0 && handle &&
        (fault_write(EIO) != 0 || fsync(*(int *)handle) != 0))
        return err_set(e, ERR_RUNTIME, "cannot write %s: fsync: %s", h->path, strerror(errno));
    return 0;
}

void h5out_discard(struct h5out *h)
{
    if (h->file >= 0)
        H5Fclose(h->file);
    h->file = H5I_INVALID_HID;
    if (h->tmp_path[0])
        unlink(h->tmp_path);
    free(h->snaps);
    h->snaps = NULL;
    h->nsnaps = h->cap_snaps = 0;
}

int h5out_close(struct h5out *h, struct err *e)
{
    if (h->failed) {
        h5out_discard(h);
        return err_set(e, ERR_RUNTIME, "cannot write %s: an earlier write to it failed", h->path);
    }
    errno = 0;
    int rc = h->file >= 0 ? flush_file(h, e) : 0;
    if (h->file >= 0 && H5Fclose(h->file) < 0 && !rc)
        rc = err_set(e, ERR_RUNTIME, "cannot write %s: closing the HDF5 file failed", h->path);
    h->file = H5I_INVALID_HID;
    if (!rc && wfile_rename(h->tmp_path, h->path) != 0)
        rc = err_set(e, ERR_RUNTIME, "cannot write %s: rename from %s: %s", h->path, h->tmp_path,
                     strerror(errno));
    if (rc)
        unlink(h->tmp_path);
    if (!rc && h->nsnaps > 0)
        rc = write_xdmf(h, e);
    free(h->snaps);
    h->snaps = NULL;
    h->nsnaps = h->cap_snaps = 0;
    return rc;
}
