/*
 * Structure classification (solver/analysis/structure.h): common neighbour
 * analysis with the fixed fcc cutoff 0.5 (1 + 1/sqrt 2) a and adaptive,
 * coordination for diamond, surface detection.
 *
 *   - 100 % fcc on fcc copper equilibrated at 300 K with the Mishin EAM;
 *   - 100 % hcp on perfect hcp; 100 % bcc on bcc; the centre of a
 *     13-atom icosahedron is icosahedral;
 *   - an intrinsic stacking fault (one close-packed layer taken out of
 *     ABC stacking) gives exactly two hcp planes, everything else fcc;
 *   - the top and bottom layers of free (001) and (111) slabs are surface,
 *     all other atoms fcc; atoms next to a vacancy are not surface;
 *   - diamond silicon is 4-coordinated, its (001) faces are surface;
 *   - pairs at the cutoff: fcc stretched/compressed along x so that the
 *     second-shell pairs sit 1e-4 Å inside, on, or 1e-4 Å outside the
 *     fixed cutoff (uniaxial compression by 14.6 %, as behind a shock):
 *     the answer flips cleanly from fcc to bcc (Bain path) at +-1e-4 Å, the neighbour
 *     relation is symmetric (bit-identical distances from both ends) even
 *     on the tie, the thread count does not matter, and adaptive CNA calls
 *     all three fcc;
 *   - the `structure` case type counts the surface and fcc atoms of a slab.
 */
#include <criterion/criterion.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/structure.h"
#include "helpers/th.h"
#include "core/velocity.h"

static long classify(struct particles *p, const struct box *b, enum structure_ref ref,
                     enum cna_mode mode, double a, int nthreads, long counts[STRUCT_NCLASSES],
                     int **cls_out)
{
    struct structure_params sp = {ref, mode, a, 0, 0, 0, 0, nthreads};
    struct err e = {0};
    cr_assert_eq(structure_params_resolve(&sp, &e), 0, "%s", e.msg);
    int *cls = malloc((size_t)p->n_owned * sizeof *cls);
    struct frame f = {0};
    cr_assert_eq(structure_classify_particles(&sp, p, b, &f, cls, &e), 0, "%s", e.msg);
    long n = structure_count(cls, p->n_owned, NULL, counts);
    frame_free(&f);
    if (cls_out)
        *cls_out = cls;
    else
        free(cls);
    return n;
}

static struct particles *lattice(enum lattice_style st, double a, const int (*orient)[3],
                                 long nx, long ny, long nz, struct box *b)
{
    struct lattice l = {st, a, {0, 0, 0}, {{0}}};
    if (orient)
        memcpy(l.orient, orient, sizeof l.orient);
    struct particles *p = particles_create(64);
    int t = particles_type_index(p, "Cu", 63.546);
    int64_t id = 1;
    long n[3] = {nx, ny, nz};
    struct err e = {0};
    cr_assert(lattice_fill(&l, n, NULL, p, t, &id, &e) > 0, "%s", e.msg);
    double cell[3];
    lattice_cell(&l, cell);
    for (int d = 0; d < 3; d++) {
        b->lo[d] = 0;
        b->hi[d] = n[d] * cell[d];
        b->bc[d] = BOUNDARY_PERIODIC;
    }
    return p;
}

Test(structure, fcc_copper_at_300K_is_all_fcc, .timeout = 60)
{
    struct box box = {0};
    struct particles *p = th_crystal(LATTICE_FCC, 3.615, 5, "Cu", 0.0, 1, &box);
    struct err e = {0};
    struct potential *pot = th_potential("style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n");
    cr_assert_eq(potential_bind(pot, p, &e), 0, "%s", e.msg);
    cr_assert_eq(velocity_maxwell(p, 600.0, 7, 1u, &e), 0, "%s", e.msg);
    struct md md;
    th_md(&md, p, &box, pot, 1);
    md.dt = 0.002;
    md.thermo = (struct thermostat){THERMOSTAT_LANGEVIN, 300.0, 0.1, 1u};
    md.seed = 11;
    for (int s = 0; s < 500; s++)
        cr_assert_eq(md_step(&md, &e), 0, "%s", e.msg);
    double T = md_temperature(&md);
    cr_assert(T > 220 && T < 380, "not thermalised: T = %g K", T);
    long c[STRUCT_NCLASSES];
    long n = classify(md.p, &md.box, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_FCC], n, "fixed cutoff: %ld of %ld fcc at %.0f K", c[STRUCT_FCC], n, T);
    n = classify(md.p, &md.box, STRUCT_REF_FCC, CNA_ADAPTIVE, 3.615, 2, c, NULL);
    cr_assert_eq(c[STRUCT_FCC], n, "adaptive: %ld of %ld fcc at %.0f K", c[STRUCT_FCC], n, T);
    md_free(&md);
}

Test(structure, perfect_hcp_bcc_are_all_hcp_bcc)
{
    struct box b = {0};
    long c[STRUCT_NCLASSES];
    struct particles *p = lattice(LATTICE_HCP, 2.556, NULL, 5, 3, 3, &b);
    long n = classify(p, &b, STRUCT_REF_HCP, CNA_FIXED, 2.556, 1, c, NULL);
    cr_assert_eq(c[STRUCT_HCP], n, "hcp fixed: %ld of %ld", c[STRUCT_HCP], n);
    n = classify(p, &b, STRUCT_REF_FCC, CNA_ADAPTIVE, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_HCP], n, "hcp adaptive: %ld of %ld", c[STRUCT_HCP], n);
    /* the fixed fcc cutoff of the same nearest-neighbour distance */
    n = classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 2.556 * M_SQRT2, 1, c, NULL);
    cr_assert_eq(c[STRUCT_HCP], n, "hcp with fcc cutoff: %ld of %ld", c[STRUCT_HCP], n);
    particles_destroy(&p);

    p = lattice(LATTICE_BCC, 2.87, NULL, 4, 4, 4, &b);
    n = classify(p, &b, STRUCT_REF_BCC, CNA_FIXED, 2.87, 1, c, NULL);
    cr_assert_eq(c[STRUCT_BCC], n, "bcc fixed: %ld of %ld", c[STRUCT_BCC], n);
    n = classify(p, &b, STRUCT_REF_FCC, CNA_ADAPTIVE, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_BCC], n, "bcc adaptive: %ld of %ld", c[STRUCT_BCC], n);
    particles_destroy(&p);
}

Test(structure, icosahedron_centre_is_icosahedral)
{
    /* 13-atom Mackay icosahedron: the centre and 12 vertices (+-1, +-phi, 0)
     * cyclically, scaled to a 2.5 Å centre-vertex distance */
    const double phi = 0.5 * (1 + sqrt(5.0)), s = 2.5 / sqrt(1 + phi * phi);
    struct particles *p = particles_create(16);
    int t = particles_type_index(p, "Cu", 63.546);
    double c0[3] = {20, 20, 20};
    particles_add(p, c0, NULL, t, 1);
    int64_t id = 2;
    for (int k = 0; k < 3; k++)
        for (int s1 = -1; s1 <= 1; s1 += 2)
            for (int s2 = -1; s2 <= 1; s2 += 2) {
                double v[3];
                v[k] = s1 * 1.0;
                v[(k + 1) % 3] = s2 * phi;
                v[(k + 2) % 3] = 0;
                double x[3] = {c0[0] + s * v[0], c0[1] + s * v[1], c0[2] + s * v[2]};
                particles_add(p, x, NULL, t, id++);
            }
    struct box b = {{0, 0, 0}, {40, 40, 40}, {BOUNDARY_FREE, BOUNDARY_FREE, BOUNDARY_FREE}, {0, 0, 0}};
    long c[STRUCT_NCLASSES];
    int *cls;
    /* vertex-vertex 2.63 Å, centre-vertex 2.5 Å: Cu's fcc cutoff 3.086 Å takes both */
    classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, &cls);
    cr_assert_eq(cls[0], STRUCT_ICO, "centre: %s", structure_class_names[cls[0]]);
    for (int i = 1; i < 13; i++)
        cr_assert_eq(cls[i], STRUCT_SURFACE, "vertex %d: %s", i, structure_class_names[cls[i]]);
    free(cls);
    classify(p, &b, STRUCT_REF_FCC, CNA_ADAPTIVE, 3.615, 1, c, &cls);
    cr_assert_eq(cls[0], STRUCT_ICO, "centre (adaptive): %s", structure_class_names[cls[0]]);
    free(cls);
    particles_destroy(&p);
}

/* Close-packed layers stacked along z with the given letters (0 = A, 1 = B,
 * 2 = C); nearest-neighbour distance d, periodic. */
static struct particles *stacking(const char *seq, double d, int nx, int ny, struct box *b)
{
    int nl = (int)strlen(seq);
    double h = d * sqrt(2.0 / 3.0), ly = sqrt(3.0) * d;
    struct particles *p = particles_create(64);
    int t = particles_type_index(p, "Cu", 63.546);
    int64_t id = 1;
    for (int k = 0; k < nl; k++) {
        int s = seq[k] - 'A';
        /* A -> B shifts by (d/2, d/(2 sqrt 3)) */
        double ox = 0.5 * d * s, oy = s * d / (2.0 * sqrt(3.0));
        for (int i = 0; i < nx; i++)
            for (int j = 0; j < ny; j++)
                for (int q = 0; q < 2; q++) {
                    double x[3] = {fmod(ox + (i + 0.5 * q) * d, nx * d),
                                   fmod(oy + (j + 0.5 * q) * ly, ny * ly), k * h};
                    particles_add(p, x, NULL, t, id++);
                }
    }
    b->lo[0] = b->lo[1] = b->lo[2] = 0;
    b->hi[0] = nx * d;
    b->hi[1] = ny * ly;
    b->hi[2] = nl * h;
    b->bc[0] = b->bc[1] = b->bc[2] = BOUNDARY_PERIODIC;
    return p;
}

Test(structure, intrinsic_stacking_fault_gives_two_hcp_planes)
{
    const double d = 3.615 / M_SQRT2;
    struct box b = {0};
    long c[STRUCT_NCLASSES];
    /* control: perfect ABC stacking from the same builder */
    struct particles *p = stacking("ABCABCABCABC", d, 4, 3, &b);
    long n = classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_FCC], n, "ABC stacking: %ld of %ld fcc", c[STRUCT_FCC], n);
    particles_destroy(&p);
    /* ABCABCAB|CABC with the B of layer 11 removed: ...A B C A C A B C... */
    const char *seq = "ABCABCABCAC";
    p = stacking(seq, d, 4, 3, &b);
    int *cls;
    n = classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, &cls);
    int per_layer = 4 * 3 * 2;
    cr_assert_eq(c[STRUCT_HCP], 2 * per_layer, "hcp atoms: %ld, two planes are %d",
                 c[STRUCT_HCP], 2 * per_layer);
    cr_assert_eq(c[STRUCT_FCC], n - 2 * per_layer);
    /* the two hcp planes are the last two layers, A in C A C and C in A C A */
    for (int i = 0; i < p->n_owned; i++) {
        int layer = i / per_layer;
        int want = (layer == 9 || layer == 10) ? STRUCT_HCP : STRUCT_FCC;
        cr_assert_eq(cls[i], want, "layer %d (%c): %s", layer, seq[layer],
                     structure_class_names[cls[i]]);
    }
    free(cls);
    n = classify(p, &b, STRUCT_REF_FCC, CNA_ADAPTIVE, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_HCP], 2 * per_layer, "adaptive hcp atoms: %ld", c[STRUCT_HCP]);
    particles_destroy(&p);
}

/* Atoms per distinct height, lowest first, in classes. */
static void check_slab(struct particles *p, const struct box *b, double layer_tol,
                       enum structure_ref ref, double a, int inner_class, enum cna_mode mode)
{
    int *cls;
    long c[STRUCT_NCLASSES];
    classify(p, b, ref, mode, a, 1, c, &cls);
    double zmin = INFINITY, zmax = -INFINITY;
    for (int i = 0; i < p->n_owned; i++) {
        zmin = fmin(zmin, p->x[3 * i + 2]);
        zmax = fmax(zmax, p->x[3 * i + 2]);
    }
    long outer = 0;
    for (int i = 0; i < p->n_owned; i++) {
        double z = p->x[3 * i + 2];
        int is_outer = z < zmin + layer_tol || z > zmax - layer_tol;
        outer += is_outer;
        int want = is_outer ? STRUCT_SURFACE : inner_class;
        cr_assert_eq(cls[i], want, "atom %d at z = %.3f (slab %.3f..%.3f): %s, expected %s", i, z,
                     zmin, zmax, structure_class_names[cls[i]], structure_class_names[want]);
    }
    cr_assert_gt(outer, 0);
    free(cls);
}

Test(structure, free_slab_surfaces_are_surface)
{
    struct box b = {0};
    struct particles *p = lattice(LATTICE_FCC, 3.615, NULL, 5, 5, 5, &b);
    b.bc[2] = BOUNDARY_FREE;
    check_slab(p, &b, 0.1, STRUCT_REF_FCC, 3.615, STRUCT_FCC, CNA_FIXED);
    check_slab(p, &b, 0.1, STRUCT_REF_FCC, 3.615, STRUCT_FCC, CNA_ADAPTIVE);
    particles_destroy(&p);
    static const int o111[3][3] = {{1, -1, 0}, {1, 1, -2}, {1, 1, 1}};
    p = lattice(LATTICE_FCC, 3.615, o111, 4, 3, 3, &b);
    b.bc[2] = BOUNDARY_FREE;
    check_slab(p, &b, 0.1, STRUCT_REF_FCC, 3.615, STRUCT_FCC, CNA_FIXED);
    particles_destroy(&p);
    p = lattice(LATTICE_DIAMOND, 5.431, NULL, 4, 4, 4, &b);
    b.bc[2] = BOUNDARY_FREE;
    check_slab(p, &b, 0.1, STRUCT_REF_DIAMOND, 5.431, STRUCT_COORD4, CNA_FIXED);
    check_slab(p, &b, 0.1, STRUCT_REF_DIAMOND, 5.431, STRUCT_COORD4, CNA_ADAPTIVE);
    particles_destroy(&p);
}

Test(structure, vacancy_neighbours_are_displaced_not_surface)
{
    struct box b = {0};
    long c[STRUCT_NCLASSES];
    struct particles *p = lattice(LATTICE_FCC, 3.615, NULL, 5, 5, 5, &b);
    unsigned char *keep = malloc((size_t)p->n_owned);
    for (int i = 0; i < p->n_owned; i++)
        keep[i] = i != 250;
    particles_compact(p, keep);
    long n = classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_NOT12], 12, "11-coordinated atoms: %ld", c[STRUCT_NOT12]);
    cr_assert_eq(c[STRUCT_SURFACE], 0);
    cr_assert_eq(c[STRUCT_FCC], n - 12);
    particles_destroy(&p);
    p = lattice(LATTICE_DIAMOND, 5.431, NULL, 3, 3, 3, &b);
    for (int i = 0; i < p->n_owned; i++)
        keep[i] = i != 100;
    particles_compact(p, keep);
    n = classify(p, &b, STRUCT_REF_DIAMOND, CNA_FIXED, 5.431, 1, c, NULL);
    cr_assert_eq(c[STRUCT_NOT4], 4, "3-coordinated Si: %ld", c[STRUCT_NOT4]);
    cr_assert_eq(c[STRUCT_COORD4], n - 4);
    cr_assert(structure_is_displaced(STRUCT_REF_DIAMOND, STRUCT_NOT4));
    cr_assert(!structure_is_displaced(STRUCT_REF_DIAMOND, STRUCT_SURFACE));
    free(keep);
    particles_destroy(&p);
}

/* fcc with x scaled so that the second-shell pairs along x are at
 * r_c + delta. */
static struct particles *strained_fcc(double delta, struct box *b)
{
    const double a = 3.615, rc = 0.5 * (1 + 1 / M_SQRT2) * a;
    struct particles *p = lattice(LATTICE_FCC, a, NULL, 5, 4, 4, b);
    double sx = (rc + delta) / a;
    for (int i = 0; i < p->n_owned; i++)
        p->x[3 * i] *= sx;
    b->hi[0] *= sx;
    /* jitter of a few 1e-10 Å: the pairs spread on both sides of the tie */
    for (int i = 0; i < p->n_owned; i++)
        p->x[3 * i] += 3e-10 * ((i * 7919) % 13 - 6) / 6.0;
    return p;
}

struct near_ctx {
    double rc;
    long n;
};
static void near_cb(void *ctx, int entry, double r2)
{
    (void)entry;
    struct near_ctx *c = ctx;
    c->n += fabs(sqrt(r2) - c->rc) < 1e-4;
}

Test(structure, pairs_at_the_cutoff_are_judged_consistently)
{
    long c[STRUCT_NCLASSES];
    struct box b = {0};
    /* 1e-4 Å inside: 14 neighbours for every atom, and their topology is
     * that of bcc -- fcc squeezed along [100] is a body-centred tetragonal
     * lattice on the Bain path; a fixed cutoff calls it bcc, the adaptive
     * cutoff (from the 12 nearest) still sees the fcc it came from */
    struct particles *p = strained_fcc(-1e-4, &b);
    long n = classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_BCC], n, "inside: %ld of %ld bcc", c[STRUCT_BCC], n);
    n = classify(p, &b, STRUCT_REF_FCC, CNA_ADAPTIVE, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_FCC], n, "inside, adaptive: %ld of %ld fcc", c[STRUCT_FCC], n);
    particles_destroy(&p);
    /* 1e-4 Å outside: plain fcc */
    p = strained_fcc(1e-4, &b);
    n = classify(p, &b, STRUCT_REF_FCC, CNA_FIXED, 3.615, 1, c, NULL);
    cr_assert_eq(c[STRUCT_FCC], n, "outside: %ld of %ld fcc", c[STRUCT_FCC], n);
    particles_destroy(&p);
    /* on the tie: whatever round-off decides, both ends decide alike */
    p = strained_fcc(0.0, &b);
    struct structure_params sp = {STRUCT_REF_FCC, CNA_FIXED, 3.615, 0, 0, 0, 0, 1};
    struct err e = {0};
    structure_params_resolve(&sp, &e);
    struct frame f = {0};
    int *cls1 = malloc((size_t)p->n_owned * sizeof *cls1), *cls2 = malloc((size_t)p->n_owned * sizeof *cls2);
    cr_assert_eq(structure_classify_particles(&sp, p, &b, &f, cls1, &e), 0);
    long pairs = 0, near = 0, in_near = 0;
    for (int i = 0; i < f.n; i++) {
        struct near_ctx nc = {sp.cutoff, 0};
        frame_query(&f, i, sp.cutoff + 1e-4, near_cb, &nc);
        near += nc.n;
    }
    for (int i = 0; i < f.n; i++)
        for (int k = f.offset[i]; k < f.offset[i + 1]; k++) {
            int j = f.origin[f.nbr[k]];
            double rk = frame_dist2(&f, i, f.nbr[k]);
            /* the list is sorted by the distances its readers recompute */
            cr_assert(k == f.offset[i] || frame_dist2(&f, i, f.nbr[k - 1]) <= rk,
                      "list of %d not sorted at %d", i, k - f.offset[i]);
            int back = 0;
            for (int q = f.offset[j]; q < f.offset[j + 1]; q++)
                if (f.origin[f.nbr[q]] == i && frame_dist2(&f, j, f.nbr[q]) == rk)
                    back = 1;
            cr_assert(back, "pair %d-%d (r = %.15g Å) seen from %d only", i, j, sqrt(rk), i);
            pairs++;
            in_near += fabs(sqrt(rk) - sp.cutoff) < 1e-4;
        }
    cr_assert_gt(in_near, 0, "no neighbour pair just inside the cutoff");
    cr_assert_gt(near, in_near, "no pair just outside the cutoff");
    sp.nthreads = 2;
    cr_assert_eq(structure_classify_particles(&sp, p, &b, &f, cls2, &e), 0);
    cr_assert_eq(memcmp(cls1, cls2, (size_t)p->n_owned * sizeof *cls1), 0,
                 "classes depend on the thread count");
    sp.mode = CNA_ADAPTIVE;
    structure_params_resolve(&sp, &e);
    cr_assert_eq(structure_classify_particles(&sp, p, &b, &f, cls2, &e), 0);
    for (int i = 0; i < p->n_owned; i++)
        cr_assert_eq(cls2[i], STRUCT_FCC, "adaptive on the tie, atom %d: %s", i,
                     structure_class_names[cls2[i]]);
    cr_log_info("%ld neighbour pairs; %ld pairs within 1e-4 Å of the cutoff, %ld of them inside",
                pairs, near, in_near);
    frame_free(&f);
    free(cls1);
    free(cls2);
    particles_destroy(&p);
}

Test(structure, bad_parameters_are_refused)
{
    struct structure_params sp = {STRUCT_REF_FCC, CNA_FIXED, 0, 0, 0, 0, 0, 1};
    struct err e = {0};
    cr_assert_eq(structure_params_resolve(&sp, &e), ERR_INPUT);
    cr_assert(strstr(e.msg, "lattice constant or a cutoff"), "%s", e.msg);
    /* a cutoff alone gives the lattice constant: the coarse DPD lattice */
    struct structure_params dp = {STRUCT_REF_FCC, CNA_FIXED, 0, 0.5 * (1 + 1 / M_SQRT2) * 7.23, 0, 0, 0, 1};
    cr_assert_eq(structure_params_resolve(&dp, &e), 0);
    cr_assert_float_eq(dp.a, 7.23, 1e-12);
}

/* The `structure` case type through cascade-solver: a free (001) slab of
 * 4 x 4 x 4 cells has 2 x 32 surface atoms and 192 fcc atoms. */
Test(structure, structure_case_counts_a_slab, .timeout = 60)
{
    const char *text = "type: structure\n"
                       "system:\n"
                       "  lattice: {style: fcc, a: 3.615, cells: [4, 4, 4]}\n"
                       "  element: Cu\n"
                       "  boundary: [periodic, periodic, free]\n"
                       "analysis: {structure: {method: adaptive}, repeat: 3}\n";
    const char *path = th_write_temp(3, "slab.yaml", text);
    char outdir[512], out[4096], rpath[600];
    snprintf(outdir, sizeof outdir, "%s/slab-out", th_temp_dir());
    const char *argv[] = {th_solver(), "run", path, "--out", outdir, "--quiet", NULL};
    int st = th_run(argv, out, sizeof out);
    cr_assert_eq(st, 0, "exit %d: %s", st, out);
    snprintf(rpath, sizeof rpath, "%s/result.json", outdir);
    json_error_t je;
    json_t *res = json_load_file(rpath, 0, &je);
    cr_assert_not_null(res, "%s", je.text);
    json_t *m = json_object_get(res, "metrics");
    double ns = json_number_value(json_object_get(json_object_get(m, "n_surface"), "value"));
    double nf = json_number_value(json_object_get(json_object_get(m, "n_fcc"), "value"));
    double t = json_number_value(json_object_get(json_object_get(m, "cna_us_per_atom"), "value"));
    cr_assert_eq(ns, 64.0, "surface atoms %g", ns);
    cr_assert_eq(nf, 192.0, "fcc atoms %g", nf);
    cr_assert_gt(t, 0.0);
    json_decref(res);
}
