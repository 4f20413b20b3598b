/* checkpoint: HDF5 checkpoint files (checkpoint.h). */
#include "output/checkpoint.h"

#include <errno.h>
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output/h5out.h"
#include "util/canon.h"
#include "util/fault.h"
#include "util/mem.h"

static int fail(struct ckpt *c, const char *what, const char *name)
{
    return err_set(c->e, ERR_RUNTIME, "%s: checkpoint %s%s%s: %s", c->path, c->where,
                   c->where[0] ? "/" : "", name, what);
}

static int read_attr_string(hid_t obj, const char *name, char *out, size_t len)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    if (a < 0)
        return -1;
    hid_t t = H5Aget_type(a);
    size_t n = H5Tget_size(t);
    int rc = -1;
    if (H5Tget_class(t) == H5T_STRING && n > 0) {
        char *buf = mem_alloc(n + 1);
        hid_t mt = H5Tcopy(H5T_C_S1);
        H5Tset_size(mt, n);
        if (buf && H5Aread(a, mt, buf) >= 0) {
            buf[n] = '\0';
            snprintf(out, len, "%s", buf);
            rc = 0;
        }
        H5Tclose(mt);
        free(buf);
    }
    H5Tclose(t);
    H5Aclose(a);
    return rc;
}

static int read_attr_double(hid_t obj, const char *name, double *v)
{
    if (H5Aexists(obj, name) <= 0)
        return -1;
    hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
    if (a < 0)
        return -1;
    int rc = H5Aread(a, H5T_NATIVE_DOUBLE, v) < 0 ? -1 : 0;
    H5Aclose(a);
    return rc;
}

int ckpt_create(struct ckpt *c, const char *path, const json_t *case_doc, const char *case_key,
                long step, double time, struct err *e)
{
    memset(c, 0, sizeof *c);
    c->e = e;
    c->writing = 1;
    c->group = -1;
    snprintf(c->path, sizeof c->path, "%s", path);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);   /* errors are reported by us */
    /* the newest file format checksums the metadata too (superblock v2+,
     * object headers), the Fletcher-32 filter the data */
    c->file = -1;
    if (fault_write(ENOSPC) != 0)
        return err_set(e, ERR_RUNTIME, "%s: cannot create checkpoint file: %s", path,
                       strerror(errno));
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    c->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    H5Pclose(fapl);
    if (c->file < 0)
        return err_set(e, ERR_RUNTIME, "%s: cannot create checkpoint file", path);
    c->group = c->file;
    h5out_attr_string(c->file, "format", CKPT_FORMAT);
    h5out_attr_double(c->file, "version", CKPT_VERSION);
    h5out_attr_string(c->file, "case_key", case_key);
    h5out_attr_double(c->file, "step", (double)step);
    h5out_attr_double(c->file, "time_ps", time);
    char *text = case_doc ? canon_json(case_doc) : NULL;
    if (case_doc && !text)
        return err_set(e, ERR_RUNTIME, "%s: cannot write checkpoint: out of memory (case)", path);
    h5out_attr_string(c->file, "case", text ? text : "{}");
    free(text);
    return 0;
}

/* The root attributes a reader checks (ckpt_open, ckpt_open_parallel). */
static int check_root(struct ckpt *c, const char *path, const char *expect_key, long *step,
                      struct err *e)
{
    char fmt[64] = "", key[64] = "";
    double version = 0, s = -1;
    if (read_attr_string(c->file, "format", fmt, sizeof fmt) != 0 || strcmp(fmt, CKPT_FORMAT) != 0)
        return err_set(e, ERR_INPUT, "%s: not a Cascade checkpoint (format attribute '%s')", path,
                       fmt);
    if (read_attr_double(c->file, "version", &version) != 0 || version != CKPT_VERSION)
        return err_set(e, ERR_INPUT,
                       "%s: checkpoint format version %g, this solver reads version %d", path,
                       version, CKPT_VERSION);
    if (read_attr_string(c->file, "case_key", key, sizeof key) != 0 ||
        (expect_key && strcmp(key, expect_key) != 0))
        return err_set(e, ERR_INPUT,
                       "%s: checkpoint of another case (job key %s, this case has %s)", path, key,
                       expect_key ? expect_key : "?");
    if (read_attr_double(c->file, "step", &s) != 0 || s < 0)
        return err_set(e, ERR_INPUT, "%s: checkpoint has no step", path);
    if (step)
        *step = (long)s;
    return 0;
}

int ckpt_open(struct ckpt *c, const char *path, const char *expect_key, long *step,
              struct err *e)
{
    memset(c, 0, sizeof *c);
    c->e = e;
    c->group = -1;
    snprintf(c->path, sizeof c->path, "%s", path);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    if (H5Fis_hdf5(path) <= 0)
        return err_set(e, ERR_INPUT, "%s: not a readable HDF5 file (truncated or corrupt "
                                     "checkpoint?)",
                       path);
    c->file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (c->file < 0)
        return err_set(e, ERR_INPUT, "%s: cannot open (truncated or corrupt checkpoint?)", path);
    c->group = c->file;
    int rc = check_root(c, path, expect_key, step, e);
    if (rc)
        ckpt_close(c);
    return rc;
}

/* Whether flag is set on any rank of a parallel checkpoint. */
static int ck_any(const struct ckpt *c, int flag)
{
    if (!c->par)
        return flag != 0;
    int in = flag != 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return out;
}

int ckpt_agree(const struct ckpt *c, int rc)
{
    if (ck_any(c, rc != 0) && !rc)
        rc = err_set_elsewhere(c->e, ERR_RUNTIME,
                               "%s: stopped: another MPI rank failed to %s the checkpoint", c->path,
                               c->writing ? "write" : "read");
    return rc;
}

int ckpt_open_parallel(struct ckpt *c, const char *path, int writing, const char *expect_key,
                       long *step, struct err *e)
{
    memset(c, 0, sizeof *c);
    c->e = e;
    c->group = -1;
    c->file = -1;
    c->par = 1;
    c->writing = writing;
    snprintf(c->path, sizeof c->path, "%s", path);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    int rc = 0;
    if (writing && fault_write(ENOSPC) != 0)
        rc = err_set(e, ERR_RUNTIME, "%s: cannot open checkpoint file: %s", path, strerror(errno));
    if ((rc = ckpt_agree(c, rc)))
        return rc;
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_fapl_mpio(fapl, MPI_COMM_WORLD, MPI_INFO_NULL);
    c->file = H5Fopen(path, writing ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl);
    H5Pclose(fapl);
    if (c->file < 0)
        rc = err_set(e, writing ? ERR_RUNTIME : ERR_INPUT,
                     "%s: cannot open through MPI-IO (truncated or corrupt checkpoint?)", path);
    c->group = c->file;
    if (!rc && !writing)
        rc = check_root(c, path, expect_key, step, e);
    if ((rc = ckpt_agree(c, rc))) {
        c->writing = 0;   /* nothing to flush */
        ckpt_close(c);
    }
    return rc;
}

int ckpt_close(struct ckpt *c)
{
    int rc = 0;
    if (c->group >= 0 && c->group != c->file)
        H5Gclose(c->group);
    c->group = -1;
    if (c->file >= 0) {
        errno = 0;
        /* parallel: every rank flushes or none (H5Fflush is collective; the
         * MPI-IO driver syncs the file there, so no descriptor to fsync) */
        if (c->writing && (ck_any(c, fault_write(ENOSPC) != 0) ||
                           ck_any(c, H5Fflush(c->file, H5F_SCOPE_GLOBAL) < 0)))
            rc = err_set(c->e, ERR_RUNTIME, "%s: cannot write checkpoint: %s", c->path,
                         errno ? strerror(errno) : "flushing the HDF5 file failed (disk full?)");
        void *handle = NULL;
        if (c->writing && !c->par && !rc &&
            H5Fget_vfd_handle(c->file, H5P_DEFAULT, &handle) >= 0 && handle &&
            (fault_write(EIO) != 0 || fsync(*(int *)handle) != 0))
            rc = err_set(c->e, ERR_RUNTIME, "%s: cannot write checkpoint: fsync: %s", c->path,
                         strerror(errno));
        if (H5Fclose(c->file) < 0 && !rc)
            rc = err_set(c->e, ERR_RUNTIME, "%s: cannot close checkpoint (disk full?)", c->path);
        if (c->par)
            rc = ckpt_agree(c, rc);
    }
    c->file = -1;
    return rc;
}

int ckpt_enter(struct ckpt *c, const char *name)
{
    if (c->group >= 0 && c->group != c->file)
        H5Gclose(c->group);
    c->group = -1;
    snprintf(c->where, sizeof c->where, "%s", name);
    hid_t g;
    if (c->writing && !c->par) {   /* the parallel writer fills groups rank 0 made */
        hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
        H5Pset_create_intermediate_group(lcpl, 1);
        g = H5Gcreate2(c->file, name, lcpl, H5P_DEFAULT, H5P_DEFAULT);
        H5Pclose(lcpl);
    } else {
        g = H5Lexists(c->file, name, H5P_DEFAULT) > 0 ? H5Gopen2(c->file, name, H5P_DEFAULT) : -1;
    }
    if (g < 0)
        return err_set(c->e, ERR_INPUT, "%s: checkpoint has no group %s", c->path, name);
    c->group = g;
    return 0;
}

/* Chunked with a Fletcher-32 checksum: a flipped bit is an error on read.
 * Also the serial phase of a parallel checkpoint (d NULL). */
static int put_array(struct ckpt *c, const char *name, hid_t memtype, hid_t filetype,
                     const void *d, long n)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = H5Screate_simple(1, dims, NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (n > 0) {
        hsize_t chunk[1] = {(hsize_t)(n < 65536 ? n : 65536)};
        H5Pset_chunk(dcpl, 1, chunk);
        H5Pset_fletcher32(dcpl);
    }
    int injected = fault_write(ENOSPC) != 0;
    hid_t ds = injected ? -1
                        : H5Dcreate2(c->group, name, filetype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int rc = 0;
    /* d NULL: the dataset only (ckpt_put_particles_layout; the ranks write it) */
    if (ds < 0 || (n > 0 && d && H5Dwrite(ds, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, d) < 0))
        rc = fail(c, injected ? "cannot write: No space left on device" : "cannot write (disk full?)",
                  name);
    if (ds >= 0)
        H5Dclose(ds);
    H5Pclose(dcpl);
    H5Sclose(space);
    return rc;
}

long ckpt_len(struct ckpt *c, const char *name)
{
    if (H5Lexists(c->group, name, H5P_DEFAULT) <= 0) {
        fail(c, "missing", name);
        return -1;
    }
    hid_t ds = H5Dopen2(c->group, name, H5P_DEFAULT);
    if (ds < 0) {
        fail(c, "unreadable", name);
        return -1;
    }
    hid_t space = H5Dget_space(ds);
    hsize_t dims[1] = {0};
    int rank = H5Sget_simple_extent_ndims(space);
    if (rank == 1)
        H5Sget_simple_extent_dims(space, dims, NULL);
    H5Sclose(space);
    H5Dclose(ds);
    if (rank != 1) {
        fail(c, "not a 1-D dataset", name);
        return -1;
    }
    return (long)dims[0];
}

static int get_array(struct ckpt *c, const char *name, hid_t memtype, void *d, long n)
{
    long have = ckpt_len(c, name);
    if (have < 0)
        return ERR_INPUT;
    if (have != n) {
        char what[96];
        snprintf(what, sizeof what, "has %ld values, expected %ld", have, n);
        return fail(c, what, name);
    }
    if (n == 0)
        return 0;
    hid_t ds = H5Dopen2(c->group, name, H5P_DEFAULT);
    int rc = 0;
    if (ds < 0 || H5Dread(ds, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, d) < 0)
        rc = fail(c, "unreadable (checksum mismatch: corrupt checkpoint?)", name);
    if (ds >= 0)
        H5Dclose(ds);
    return rc ? ERR_INPUT : 0;
}

int ckpt_put_doubles(struct ckpt *c, const char *name, const double *d, long n)
{
    return put_array(c, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, d, n);
}
int ckpt_put_i64(struct ckpt *c, const char *name, const int64_t *d, long n)
{
    return put_array(c, name, H5T_NATIVE_INT64, H5T_STD_I64LE, d, n);
}
int ckpt_put_ints(struct ckpt *c, const char *name, const int *d, long n)
{
    return put_array(c, name, H5T_NATIVE_INT, H5T_STD_I32LE, d, n);
}
int ckpt_put_u32(struct ckpt *c, const char *name, const uint32_t *d, long n)
{
    return put_array(c, name, H5T_NATIVE_UINT32, H5T_STD_U32LE, d, n);
}
int ckpt_put_bytes(struct ckpt *c, const char *name, const void *d, long n)
{
    return put_array(c, name, H5T_NATIVE_UCHAR, H5T_STD_U8LE, d, n);
}
int ckpt_get_bytes(struct ckpt *c, const char *name, void *d, long n)
{
    return get_array(c, name, H5T_NATIVE_UCHAR, d, n);
}
int ckpt_put_double(struct ckpt *c, const char *name, double v)
{
    return ckpt_put_doubles(c, name, &v, 1);
}
int ckpt_put_long(struct ckpt *c, const char *name, long v)
{
    int64_t x = v;
    return ckpt_put_i64(c, name, &x, 1);
}

int ckpt_get_doubles(struct ckpt *c, const char *name, double *d, long n)
{
    return get_array(c, name, H5T_NATIVE_DOUBLE, d, n);
}
int ckpt_get_i64(struct ckpt *c, const char *name, int64_t *d, long n)
{
    return get_array(c, name, H5T_NATIVE_INT64, d, n);
}
int ckpt_get_ints(struct ckpt *c, const char *name, int *d, long n)
{
    return get_array(c, name, H5T_NATIVE_INT, d, n);
}
int ckpt_get_u32(struct ckpt *c, const char *name, uint32_t *d, long n)
{
    return get_array(c, name, H5T_NATIVE_UINT32, d, n);
}
int ckpt_get_double(struct ckpt *c, const char *name, double *v)
{
    return ckpt_get_doubles(c, name, v, 1);
}
int ckpt_get_long(struct ckpt *c, const char *name, long *v)
{
    int64_t x = 0;
    int rc = ckpt_get_i64(c, name, &x, 1);
    *v = (long)x;
    return rc;
}

int ckpt_get_rows(struct ckpt *c, const char *name, int ncols, double **rows, long *nrows)
{
    long nv = ckpt_len(c, name);
    if (nv < 0)
        return ERR_INPUT;
    if (ncols <= 0 || nv % ncols != 0) {
        char what[96];
        snprintf(what, sizeof what, "%ld values are not rows of %d", nv, ncols);
        fail(c, what, name);
        return ERR_INPUT;
    }
    double *r = mem_alloc((size_t)(nv > 0 ? nv : 1) * sizeof *r);
    if (!r)
        return err_nomem(c->e, "checkpoint rows");
    int rc = ckpt_get_doubles(c, name, r, nv);
    if (rc) {
        free(r);
        return rc;
    }
    free(*rows);
    *rows = r;
    *nrows = nv / ncols;
    return 0;
}

/* A value the file holds but no run can have: the file is refused. */
static int bad(struct ckpt *c, const char *what, const char *name)
{
    fail(c, what, name);
    c->e->code = ERR_INPUT;
    return ERR_INPUT;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

static int particle_columns(const struct particles *p, struct ckpt_col *col)
{
    const struct ckpt_col fixed[9] = {
        {"x", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 3, p->x},
        {"v", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 3, p->v},
        {"f", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 3, p->f},
        {"type", H5T_NATIVE_INT, H5T_STD_I32LE, 1, p->type},
        {"id", H5T_NATIVE_INT64, H5T_STD_I64LE, 1, p->id},
        {"mask", H5T_NATIVE_UINT32, H5T_STD_U32LE, 1, p->mask},
        {"image", H5T_NATIVE_INT, H5T_STD_I32LE, 3, p->image},
        {"pe", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 1, p->pe},
        {"virial", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, 6, p->virial},
    };
    memcpy(col, fixed, sizeof fixed);
    for (int k = 0; k < p->nfields; k++) {
        col[9 + k] = (struct ckpt_col){"", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, p->fields[k].ncomp,
                                   p->fields[k].data};
        snprintf(col[9 + k].name, sizeof col[9 + k].name, "field_%s", p->fields[k].name);
    }
    return 9 + p->nfields;
}

/* The group's count and type table; then every column with n rows, the
 * data of p (with_data) or none (the parallel layout). */
static int put_particle_group(struct ckpt *c, const char *name, const struct particles *p, long n,
                              int with_data)
{
    int rc = ckpt_enter(c, name);
    double masses[PARTICLES_MAX_TYPES];
    for (int t = 0; t < p->ntypes; t++)
        masses[t] = p->mass[t];
    if (!rc)
        rc = ckpt_put_long(c, "n", n);
    if (!rc)
        rc = ckpt_put_doubles(c, "type_mass", masses, p->ntypes);
    /* type names as one '\n'-joined string in an attribute */
    if (!rc) {
        char names[PARTICLES_MAX_TYPES * 17 + 1] = "";
        for (int t = 0; t < p->ntypes; t++) {
            strcat(names, p->type_name[t]);
            strcat(names, "\n");
        }
        h5out_attr_string(c->group, "type_names", names);
    }
    struct ckpt_col col[9 + PARTICLES_MAX_FIELDS];
    int ncol = particle_columns(p, col);
    for (int q = 0; !rc && q < ncol; q++)
        rc = put_array(c, col[q].name, col[q].memtype, col[q].filetype,
                       with_data ? col[q].data : NULL, (long)col[q].ncomp * n);
    return rc;
}

int ckpt_put_particles(struct ckpt *c, const char *name, const struct particles *p)
{
    return put_particle_group(c, name, p, p->n_owned, 1);
}

int ckpt_put_particles_layout(struct ckpt *c, const char *name, const struct particles *p,
                              long n_total)
{
    return put_particle_group(c, name, p, n_total, 0);
}

/* Values [first, first + count) of a 1-D dataset from d, one collective
 * transfer (a rank with count 0 selects nothing but takes part). */
static int put_part(struct ckpt *c, const struct ckpt_col *col, long first, long count)
{
    int injected = ck_any(c, fault_write(ENOSPC) != 0);
    hid_t ds = injected ? -1 : H5Dopen2(c->group, col->name, H5P_DEFAULT);
    if (ck_any(c, ds < 0)) {
        if (ds >= 0)
            H5Dclose(ds);
        return fail(c, injected ? "cannot write: No space left on device" : "missing", col->name);
    }
    hsize_t start[1] = {(hsize_t)first}, len[1] = {(hsize_t)(count > 0 ? count : 1)};
    hid_t fs = H5Dget_space(ds), ms = H5Screate_simple(1, len, NULL);
    int bad = fs < 0 || ms < 0;
    if (!bad && count > 0)
        bad = H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, len, NULL) < 0;
    else if (!bad)
        bad = H5Sselect_none(fs) < 0 || H5Sselect_none(ms) < 0;
    static const double nothing = 0;
    hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
    H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);   /* the Fletcher-32 filter needs it */
    bad |= H5Dwrite(ds, col->memtype, ms, fs, dxpl, count > 0 ? col->data : &nothing) < 0;
    H5Pclose(dxpl);
    if (ms >= 0)
        H5Sclose(ms);
    if (fs >= 0)
        H5Sclose(fs);
    H5Dclose(ds);
    return ck_any(c, bad) ? fail(c, "cannot write (disk full?)", col->name) : 0;
}

int ckpt_put_columns(struct ckpt *c, const struct ckpt_col *col, int ncol, long n, int with_data)
{
    int rc = 0;
    for (int q = 0; !rc && q < ncol; q++)
        rc = put_array(c, col[q].name, col[q].memtype, col[q].filetype,
                       with_data ? col[q].data : NULL, (long)col[q].ncomp * n);
    return rc;
}

int ckpt_put_columns_part(struct ckpt *c, const struct ckpt_col *col, int ncol, long first,
                          long count)
{
    int rc = 0;
    for (int q = 0; !rc && q < ncol; q++)
        if (col[q].ncomp > 0)   /* an empty column (no state variables) was written whole */
            rc = put_part(c, &col[q], first * col[q].ncomp, count * col[q].ncomp);
    return rc;
}

int ckpt_has(struct ckpt *c, const char *name)
{
    return H5Lexists(c->group, name, H5P_DEFAULT) > 0;
}

int ckpt_put_particles_part(struct ckpt *c, const char *name, const struct particles *p,
                            long offset)
{
    int rc = ckpt_agree(c, ckpt_enter(c, name));
    struct ckpt_col col[9 + PARTICLES_MAX_FIELDS];
    int ncol = particle_columns(p, col);
    for (int q = 0; !rc && q < ncol; q++)
        rc = put_part(c, &col[q], offset * col[q].ncomp, (long)p->n_owned * col[q].ncomp);
    return rc;
}

int ckpt_get_particles(struct ckpt *c, const char *name, struct particles *p)
{
    int rc = ckpt_enter(c, name);
    long n = 0;
    if (!rc)
        rc = ckpt_get_long(c, "n", &n);
    if (!rc && (n < 0 || n > 2000000000L))
        rc = fail(c, "impossible particle count", "n");
    long nt = rc ? 0 : ckpt_len(c, "type_mass");
    if (!rc && nt != p->ntypes) {
        char what[96];
        snprintf(what, sizeof what, "has %ld particle types, the case has %d", nt, p->ntypes);
        rc = fail(c, what, "type_mass");
    }
    if (rc)
        return ERR_INPUT;
    particles_clear_ghosts(p);
    if ((rc = particles_reserve(p, (int)n, c->e)))
        return rc;
    /* the arrays hold n owned particles from here on */
    p->n_owned = (int)n;
    if (!rc) rc = ckpt_get_doubles(c, "x", p->x, 3 * n);
    if (!rc) rc = ckpt_get_doubles(c, "v", p->v, 3 * n);
    if (!rc) rc = ckpt_get_doubles(c, "f", p->f, 3 * n);
    if (!rc) rc = ckpt_get_ints(c, "type", p->type, n);
    if (!rc) rc = ckpt_get_i64(c, "id", p->id, n);
    if (!rc) rc = ckpt_get_u32(c, "mask", p->mask, n);
    if (!rc) rc = ckpt_get_ints(c, "image", p->image, 3 * n);
    if (!rc) rc = ckpt_get_doubles(c, "pe", p->pe, n);
    if (!rc) rc = ckpt_get_doubles(c, "virial", p->virial, 6 * n);
    for (int k = 0; !rc && k < p->nfields; k++) {
        char fname[64];
        snprintf(fname, sizeof fname, "field_%s", p->fields[k].name);
        rc = ckpt_get_doubles(c, fname, p->fields[k].data, (long)p->fields[k].ncomp * n);
    }
    for (long i = 0; !rc && i < n; i++) {
        p->origin[i] = (int)i;
        if (p->type[i] < 0 || p->type[i] >= p->ntypes)
            rc = bad(c, "type index out of range", "type");
        else if (p->id[i] < 1)
            rc = bad(c, "an id below 1", "id");
        for (int d = 0; !rc && d < 3; d++)
            if (!isfinite(p->x[3 * i + d]) || !isfinite(p->v[3 * i + d]) ||
                !isfinite(p->f[3 * i + d])) {
                char what[96];
                snprintf(what, sizeof what, "a non-finite position, velocity or force (id %lld)",
                         (long long)p->id[i]);
                rc = bad(c, what, "x/v/f");
            }
    }
    /* ids unique: a sorted copy, neighbours compared */
    int64_t *ids = rc || n == 0 ? NULL : mem_alloc((size_t)n * sizeof *ids);
    if (!rc && n > 0 && !ids)
        rc = err_nomem(c->e, "checkpoint ids");
    if (ids) {
        memcpy(ids, p->id, (size_t)n * sizeof *ids);
        qsort(ids, (size_t)n, sizeof *ids, cmp_i64);
        for (long i = 1; !rc && i < n; i++)
            if (ids[i] == ids[i - 1]) {
                char what[64];
                snprintf(what, sizeof what, "id %lld given twice", (long long)ids[i]);
                rc = bad(c, what, "id");
            }
        free(ids);
    }
    if (rc)
        p->n_owned = 0;
    return rc;
}

int ckpt_put_box(struct ckpt *c, const char *name, const struct box *b)
{
    int rc = ckpt_enter(c, name);
    int bc[3] = {(int)b->bc[0], (int)b->bc[1], (int)b->bc[2]};
    if (!rc) rc = ckpt_put_doubles(c, "lo", b->lo, 3);
    if (!rc) rc = ckpt_put_doubles(c, "hi", b->hi, 3);
    if (!rc) rc = ckpt_put_ints(c, "boundary", bc, 3);
    /* only a tilted box has the record: orthogonal checkpoints are as before */
    if (!rc && box_tilted(b)) rc = ckpt_put_doubles(c, "tilt", b->tilt, 3);
    return rc;
}

int ckpt_get_box(struct ckpt *c, const char *name, struct box *b)
{
    int rc = ckpt_enter(c, name);
    int bc[3];
    struct box nb = {0};
    if (!rc) rc = ckpt_get_doubles(c, "lo", nb.lo, 3);
    if (!rc) rc = ckpt_get_doubles(c, "hi", nb.hi, 3);
    if (!rc) rc = ckpt_get_ints(c, "boundary", bc, 3);
    for (int d = 0; !rc && d < 3; d++) {
        if (bc[d] != (int)b->bc[d])
            rc = fail(c, "boundary differs from the case", "boundary");
        nb.bc[d] = b->bc[d];
    }
    /* the case's box says whether there is a tilt to read (the case file
     * is the same at a restart) */
    if (!rc && box_tilted(b)) rc = ckpt_get_doubles(c, "tilt", nb.tilt, 3);
    if (!rc)
        *b = nb;
    return rc;
}
