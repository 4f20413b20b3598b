/* md_system: lattice / data-file / XYZ systems for MD cases. */
#include "input/md_system.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/elements.h"
#include "core/halo.h"
#include "core/halo_scatter.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "input/config_read.h"

static int read_boundary(struct cfg_obj *s, struct box *b)
{
    int rc = 0;
    char path[CFG_PATH_MAX];
    snprintf(path, sizeof path, "%s.boundary", s->path);
    json_t *arr = json_object_get(s->node, "boundary");
    cfg_allow(s, "boundary");
    if (!arr) {
        json_t *def = json_pack("[sss]", "periodic", "periodic", "periodic");
        json_object_set_new(s->node, "boundary", def);
        arr = def;
    }
    if (!json_is_array(arr) || json_array_size(arr) != 3)
        return cfg_error_at(s->cfg, path, "must be a list of 3 boundary kinds (periodic, free, "
                                          "fixed)");
    for (int d = 0; d < 3 && !rc; d++) {
        json_t *v = json_array_get(arr, (size_t)d);
        const char *name = json_is_string(v) ? json_string_value(v) : "";
        int k = -1;
        for (int q = 0; boundary_names[q]; q++)
            if (strcmp(boundary_names[q], name) == 0)
                k = q;
        if (k < 0) {
            char ip[CFG_PATH_MAX];
            snprintf(ip, sizeof ip, "%s[%d]", path, d);
            rc = cfg_error_at(s->cfg, ip, "unknown boundary '%s' (one of: periodic, free, fixed)",
                              name);
        }
        b->bc[d] = (enum boundary)k;
    }
    return rc;
}

int md_read_max_particles(struct cfg_obj *o, long *max)
{
    /* max_particles bounds memory, not the physics: without the key the
     * default is used but not written into the case, so the job keys of
     * existing cases do not change */
    int given;
    *max = CONFIG_MAX_ATOMS_DEFAULT;
    return cfg_int_opt(o, "max_particles", CFG_RANGE(1, MD_SYSTEM_MAX_PARTICLES_CAP), max,
                       &given);
}

int md_check_count(struct cfg_obj *o, const char *key, double count, long max, const char *what)
{
    if (count <= (double)max)
        return 0;
    char kp[CFG_PATH_MAX];
    snprintf(kp, sizeof kp, "%s.%s", o->path, key);
    int given = json_object_get(o->node, "max_particles") != NULL;
    return cfg_error_at(o->cfg, kp, "%s %.4g atoms, more than %s.max_particles = %ld%s", what,
                        count, o->path, max, given ? "" : " (the default; set it to allow more)");
}

/* The box split->plan is given (md_system_split.on_extent): b, each
 * non-periodic axis cut to [lo, hi] where the extent is not empty. */
static void extent_box(const struct box *b, const double lo[3], const double hi[3],
                       struct box *out)
{
    *out = *b;
    for (int d = 0; d < 3; d++)
        if (b->bc[d] != BOUNDARY_PERIODIC && lo[d] <= hi[d]) {
            out->lo[d] = lo[d];
            out->hi[d] = hi[d];
        }
}

/* The extent of p's owned atoms. */
static void particles_extent(const struct particles *p, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], p->x[3 * i + d]);
            hi[d] = fmax(hi[d], p->x[3 * i + d]);
        }
}

/* The serial displacement of the atom built i-th is the i-th triple of
 * uniforms of one sequence; a rank holding the atoms of its brick (built
 * in id order, id = i + 1) runs through the sequence and keeps its own. */
static int displace_atoms(struct particles *p, uint64_t seed, double displace, int by_id,
                          struct err *e)
{
    struct rng_seq *r = rng_seq_create(seed ^ 0x5eedd15ace1ull);
    if (!r)
        return err_nomem(e, "rng");
    long next = 0;
    for (int i = 0; i < p->n_owned; i++) {
        long at = by_id ? (long)(p->id[i] - 1) : i;
        for (; next < at; next++)
            for (int d = 0; d < 3; d++)
                (void)rng_seq_uniform(r);
        next++;
        for (int d = 0; d < 3; d++)
            p->x[3 * i + d] += displace * (2.0 * rng_seq_uniform(r) - 1.0);
    }
    rng_seq_destroy(&r);
    return 0;
}

/* What read_file needs of the system section. */
struct file_read {
    struct cfg_obj *root, *s;
    const char *file;
    int has_data;
    const char *const *elements;
    int nelements;
    long max_particles;
    int tilt_ok;
    const struct region *region;   /* NULL: none */
    double displace;
    uint64_t seed;
};

/* The whole file read and checked into p and b, the region's atoms kept
 * and displaced as in a serial run (displacement k to the k-th atom kept,
 * in the file's order). */
static int read_file(const struct file_read *fr, struct particles *p, struct box *b,
                     struct err *e)
{
    char path[4096], keypath[CFG_PATH_MAX];
    snprintf(keypath, sizeof keypath, "%s.%s", fr->s->path,
             fr->has_data ? "read_data" : "read_xyz");
    if (cfg_find_file(fr->s->cfg, fr->file, path, sizeof path) != 0)
        return cfg_error_at(fr->s->cfg, keypath, "cannot read '%s'", fr->file);
    enum boundary keep[3] = {b->bc[0], b->bc[1], b->bc[2]};
    struct config_rules rules = config_rules_default();
    for (int d = 0; d < 3; d++)
        rules.bc[d] = b->bc[d];
    rules.max_atoms = fr->max_particles;
    /* only the md engine has tilted periodic images (core/ghost.h);
     * other case types refuse a tilted file at its tilt line */
    rules.allow_tilt = fr->tilt_ok;
    json_t *type = json_object_get(fr->root->node, "type");
    char who[96];
    snprintf(who, sizeof who, "case type %s", json_is_string(type) ? json_string_value(type)
                                                                     : "md");
    rules.who = who;
    int rc;
    if (fr->has_data) {
        rc = config_read_lammps_data(path, fr->elements, fr->nelements, &rules, p, b, e);
    } else {
        int pbc[3];
        rc = config_read_extxyz(path, &rules, p, b, pbc, e);
    }
    for (int d = 0; d < 3; d++)
        b->bc[d] = keep[d];
    if (!rc && fr->region) {
        unsigned char *keepmask = malloc((size_t)(p->n_owned ? p->n_owned : 1));
        rc = keepmask ? 0 : err_nomem(e, "region");
        for (int i = 0; !rc && i < p->n_owned; i++)
            keepmask[i] = (unsigned char)region_contains(fr->region, p->x + 3 * i);
        if (!rc)
            particles_compact(p, keepmask);
        free(keepmask);
    }
    if (!rc && fr->displace > 0)
        rc = displace_atoms(p, fr->seed, fr->displace, 0, e);
    return rc;
}

int md_system_read(struct cfg_obj *root, uint64_t seed, struct particles **pout, struct box *b,
                   struct md_system_info *info)
{
    return md_system_read_split(root, seed, NULL, pout, b, info, NULL);
}

int md_system_read_split(struct cfg_obj *root, uint64_t seed, const struct md_system_split *split,
                         struct particles **pout, struct box *b, struct md_system_info *info,
                         struct halo **halo_out)
{
    struct halo *halo = NULL;
    if (halo_out)
        *halo_out = NULL;
    struct cfg_obj s;
    int rc = cfg_section_required(root, "system", &s);
    if (rc)
        return rc;
    memset(info, 0, sizeof *info);
    memset(b, 0, sizeof *b);
    int has_lat, has_data, has_xyz;
    struct cfg_obj lat;
    const char *data_file = NULL, *xyz_file = NULL, *element = NULL;
    if ((rc = cfg_section_opt(&s, "lattice", &lat, &has_lat)) ||
        (rc = cfg_string_opt(&s, "read_data", &data_file, &has_data)) ||
        (rc = cfg_string_opt(&s, "read_xyz", &xyz_file, &has_xyz)))
        return rc;
    if (has_lat + has_data + has_xyz != 1)
        return cfg_error_at(s.cfg, s.path,
                            "give exactly one of 'lattice', 'read_data' or 'read_xyz' (found %d)",
                            has_lat + has_data + has_xyz);
    if ((rc = read_boundary(&s, b)))
        return rc;
    double displace, mass;
    if ((rc = cfg_real(&s, "displace", 0.0, CFG_GE(0), &displace)) ||
        (rc = cfg_real(&s, "mass", 0.0, CFG_GE(0), &mass)) ||
        (rc = md_read_max_particles(&s, &info->max_particles)))
        return rc;
    struct region region;
    int has_region;
    struct cfg_obj ro;
    if ((rc = cfg_section_opt(&s, "region", &ro, &has_region)))
        return rc;
    if (has_region && (rc = region_read(&ro, &region)))
        return rc;

    const char *elements[PARTICLES_MAX_TYPES];
    int nelements = 0;
    if (has_lat) {
        static const long one[3] = {1, 1, 1};
        const double zero[3] = {0, 0, 0};
        int style;
        info->from_lattice = 1;
        if ((rc = cfg_enum(&lat, "style", NULL, lattice_style_names, &style)) ||
            (rc = cfg_real(&lat, "a", CFG_REQUIRED, CFG_GT(0), &info->lattice.a)) ||
            (rc = cfg_ints(&lat, "cells", 3, one, CFG_GE(1), info->cells)) ||
            (rc = cfg_reals(&lat, "origin", 3, zero, CFG_ANY, info->lattice.origin)))
            return rc;
        long orient[9];
        static const long ident[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        if ((rc = cfg_ints(&lat, "orient", 9, ident, CFG_RANGE(-20, 20), orient)))
            return rc;
        for (int k = 0; k < 9; k++)
            info->lattice.orient[k / 3][k % 3] = (int)orient[k];
        info->lattice.style = (enum lattice_style)style;
        char why[128];
        if (lattice_check_orient(&info->lattice, why, sizeof why) != 0) {
            char kp[CFG_PATH_MAX];
            snprintf(kp, sizeof kp, "%s.orient", lat.path);
            return cfg_error_at(s.cfg, kp, "%s", why);
        }
        /* before anything is allocated, also in a shallow read (resolve):
         * all the sites of the cells, as lattice_fill visits them before the
         * region keeps some */
        int ns = lattice_cell_sites(&info->lattice);
        if (ns < 0)
            return err_nomem(s.cfg->err, "lattice sites");
        double nsites = (double)info->cells[0] * (double)info->cells[1] *
                        (double)info->cells[2] * ns;
        char what[128];
        snprintf(what, sizeof what, "%ld x %ld x %ld cells of %d sites are", info->cells[0],
                 info->cells[1], info->cells[2], ns);
        if ((rc = md_check_count(&s, "lattice.cells", nsites, info->max_particles, what)))
            return rc;
        if ((rc = cfg_close(&lat)))
            return rc;
        if ((rc = cfg_string(&s, "element", NULL, &element)))
            return rc;
    } else if (has_data) {
        if ((rc = cfg_strings(&s, "elements", 0, elements, PARTICLES_MAX_TYPES, &nelements)))
            return rc;
    }
    if ((rc = cfg_close(&s)))
        return rc;
    if (s.cfg->shallow)
        return 0;

    struct particles *p = particles_create(1024);
    if (!p)
        return err_nomem(s.cfg->err, "particles");
    struct err *e = s.cfg->err;
    if (has_lat) {
        double m = mass > 0 ? mass : element_mass(element);
        int t = particles_type_index(p, element, m);
        int64_t next_id = 1;
        double cell[3];
        lattice_cell(&info->lattice, cell);
        for (int d = 0; d < 3; d++) {
            b->lo[d] = info->lattice.origin[d];
            b->hi[d] = info->lattice.origin[d] + info->cells[d] * cell[d];
        }
        /* bricks: each rank builds the sites of its own brick only */
        struct box plan_box = *b;
        if (split && split->on_extent) {
            double lo[3], hi[3];
            if (lattice_extent(&info->lattice, info->cells, has_region ? &region : NULL, lo, hi,
                               e) < 0) {
                particles_destroy(&p);
                return ERR_RUNTIME;
            }
            extent_box(b, lo, hi, &plan_box);
        }
        if (split && (rc = split->plan(split->ctx, &plan_box, &halo))) {
            particles_destroy(&p);
            return rc;
        }
        rc = lattice_fill_where(&info->lattice, info->cells, has_region ? &region : NULL,
                                halo ? decomp_owns_point : NULL, halo ? &halo->dc : NULL, p, t,
                                &next_id, e) < 0
                 ? ERR_RUNTIME
                 : 0;
        if (halo)
            rc = halo_adopt(halo, p, rc, e);
    } else {
        const struct parallel *par = split ? split->par : NULL;
        /* under mpirun with more than one rank only rank 0 reads and
         * checks the file; the others wait for its verdict and then for
         * their atoms (halo_scatter.h), so their memory never holds the
         * whole file */
        int root_reads = par && par->size > 1;
        struct file_read fr = {root, &s, has_data ? data_file : xyz_file, has_data, elements,
                               nelements, info->max_particles, split && split->tilt_ok,
                               has_region ? &region : NULL, displace, seed};
        if (!root_reads || par->rank == 0)
            rc = read_file(&fr, p, b, e);
        if (root_reads) {
            long n = 0;
            double ext[6];   /* lo, hi: rank 0's, the file's atoms */
            particles_extent(p, ext, ext + 3);
            rc = parallel_bcast_err(par, rc, e);
            if (!rc)
                rc = halo_scatter_header(par, p, b, &n, e);
            if (!rc && split->on_extent)
                rc = parallel_bcast_bytes(par, ext, sizeof ext, e);
            /* the same box on every rank: the same plan */
            struct box plan_box = *b;
            if (split->on_extent)
                extent_box(b, ext, ext + 3, &plan_box);
            if (!rc && (rc = split->plan(split->ctx, &plan_box, &halo)) == 0)
                rc = halo_scatter(par, halo, p, n, e);
            if (halo)
                rc = halo_adopt(halo, p, rc, e);
        } else if (!rc && split) {
            struct box plan_box = *b;
            if (split->on_extent) {
                double lo[3], hi[3];
                particles_extent(p, lo, hi);
                extent_box(b, lo, hi, &plan_box);
            }
            if ((rc = split->plan(split->ctx, &plan_box, &halo)) == 0 && halo)
                rc = halo_distribute(halo, p, e);
        }
    }
    if (!rc && halo && displace > 0 && has_lat)
        rc = displace_atoms(p, seed, displace, 1, e);
    else if (!rc && displace > 0 && has_lat)
        rc = displace_atoms(p, seed, displace, 0, e);
    info->natoms = halo ? halo->natoms : p->n_owned;
    if (!rc && info->natoms == 0)
        rc = cfg_error_at(s.cfg, s.path, "the system has no atoms (check the region)");
    if (rc) {
        particles_destroy(&p);
        if (halo)
            halo_free(halo);
        free(halo);
        return rc;
    }
    if (halo_out)
        *halo_out = halo;
    *pout = p;
    return 0;
}
