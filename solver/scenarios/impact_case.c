/*
 * impact_case: a cluster hitting a crystal surface (`type: cluster_impact`),
 * Guo & Yang 2005, section 3: Cu clusters of 14, 128 and 1052 atoms at
 * 10 km/s on Cu(001), 0 K, 10 ps; a 260-atom Si cluster on Si(001).
 *
 *   target:
 *     lattice: fcc            fcc | bcc | diamond; the top face is (001), normal +z
 *     element: Cu
 *     a: 3.615                Å (left out with the handshake's
 *                             thermal.from_potential: impact_from_potential.h)
 *     cells: [20, 20, 15]     cubic cells along x [100], y [010], z [001]
 *     temperature: 0          K (Maxwell-Boltzmann velocities, and the bath
 *                             of the damped layer)
 *     boundary: fixed_damped  fixed_damped | handshake (impact_boundary.h;
 *                             handshake: solver/scenarios/handshake_impact.h)
 *     fixed_thickness: 6.0    Å, at least the potential cutoff
 *     damped_thickness: 10.0  Å
 *     damping_time: 0.05      ps
 *   cluster:
 *     lattice, element, a     default: the target's
 *     atoms: 128              exact count of the spherical cut (cluster_build.h)
 *     center: [fx, fy, fz]    optional centre of the cut (units of a)
 *     speed: 10.0             km/s, straight down (-z)
 *     gap: 0                  Å between the cluster's lowest atom and the
 *                             surface at t = 0 (0: the potential cutoff + 1 Å)
 *   potential: {...}
 *   md:
 *     timestep: 0.001         ps
 *     steps: 10000
 *     skin: 1.0               Å
 *     max_displacement: 0.1   largest step of the fastest atom, as a fraction
 *                             of the nearest-neighbour distance
 *   analysis: {every: 100, structure: {...}}   (md_analysis.h)
 *   output: {...}
 *
 * The cluster is centred over the middle of the top face.  Refused: a
 * cluster wider than the free part of the top face, a target with no free
 * interior, a fixed layer thinner than the cutoff, and a time step that
 * moves the projectile more than max_displacement nearest-neighbour
 * distances per step or that the stability check rejects.
 *
 * Metrics: sizes, impact energy, the displaced-atom count (peak, time of
 * the peak, final), sputtered atoms and groups, crater depth, volume,
 * top-view widths along [100] and [110] and their ratio, rim height, and the
 * energy the boundary absorbed.  Series: md_analysis.h.
 *
 * Under mpirun (`parallel` section, docs/parallel.md) a fixed_damped target
 * runs on the MD bricks: each rank builds its brick's target sites and
 * cluster atoms with the ids of a serial build, marks the layers on its
 * own atoms, and the analyses run on rank 0 over the gathered atoms at
 * analysis steps (analysis/md_analysis_bricks.h).  A handshake target
 * runs on the same bricks: its MPM side is built whole on every rank
 * before the bricks are cut (the box grows by the copies' shell), each
 * rank keeps the copies of regions II and III in its brick, and region I
 * reaches the MPM of every rank through couple/handshake_bricks.h (with
 * target.handshake.thermal the bath acts on each rank's copies of region
 * II, its sums over the ranks: couple/handshake_thermal.h).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stdio.h>

#include "core/elements.h"
#include "core/halo.h"
#include "core/parallel.h"
#include "core/units.h"
#include "core/velocity.h"
#include "engine/models.h"
#include "md/md_settings.h"
#include "scenarios/case_type.h"
#include "scenarios/cluster_build.h"
#include "scenarios/impact_boundary.h"
#include "scenarios/impact_from_potential.h"
#include "analysis/md_analysis.h"
#include "analysis/md_analysis_bricks.h"
#include "md/md_bricks.h"
#include "analysis/stacking_faults.h"
#include "output/md_output.h"
#include "input/md_system.h"
#include "md/md_timestep.h"

struct impact {
    struct md md;
    struct md_analysis an;
    struct impact_boundary bnd;
    struct md_model model;
    struct impact_boundary_model bmodel;
    int md_index;              /* the md's place among the engine's models */
    struct md_output out;
    long peak;                 /* displaced atoms: largest count and its time */
    double peak_t;
    double *restored_rows;     /* thermo rows read from a checkpoint */
    long nrestored;
    long steps;
    long ntarget, ncluster;
    double speed;              /* Å/ps */
    double impact_energy;      /* eV */
    double surface;            /* Å: top layer height */
    double cluster_radius;     /* Å */
    double center_frac[3];
    double lo[3], hi[3];       /* target extent (atom positions) */
    double a;
    /* target.handshake.thermal.from_potential: the document before it was
     * read, with what its second read needs, and that read's case (the
     * run's) once a(T) and the constants are computed */
    json_t *doc;
    char *base_dir;
    struct case_common common;
    int tlat;
    struct impact *at_T;
};

static const char *const impact_lattices[] = {"fcc", "bcc", "diamond", NULL};
static const enum lattice_style impact_styles[] = {LATTICE_FCC, LATTICE_BCC, LATTICE_DIAMOND};
static const enum structure_ref impact_refs[] = {STRUCT_REF_FCC, STRUCT_REF_BCC,
                                                 STRUCT_REF_DIAMOND};

struct impact_spec {
    int tlat, clat;
    const char *telement, *celement;
    double ta, ca, temperature, speed, gap, dt, skin, maxdisp;
    long cells[3], natoms, steps;
    long max_particles;   /* target.max_particles */
    int has_center;
    double center[3];
};

static int read_spec(struct cfg_obj *root, struct impact_spec *s, struct impact_boundary *b)
{
    struct cfg_obj to, co;
    int rc;
    static const long cells_def[3] = {20, 20, 15};
    int a_given = 1;
    if ((rc = cfg_section_required(root, "target", &to)) ||
        (rc = cfg_enum(&to, "lattice", "fcc", impact_lattices, &s->tlat)) ||
        (rc = cfg_string(&to, "element", NULL, &s->telement)))
        return rc;
    /* from_potential computes a(T): target.a stays out (s->ta is then 0
     * until the potential's 0 K lattice constant is known) */
    if (impact_from_potential_given(to.node)) {
        if ((rc = cfg_real_opt(&to, "a", CFG_GT(0), &s->ta, &a_given)))
            return rc;
    } else if ((rc = cfg_real(&to, "a", CFG_REQUIRED, CFG_GT(0), &s->ta)))
        return rc;
    if (!a_given)
        s->ta = 0;
    else if (impact_from_potential_given(to.node))
        return cfg_error_at(root->cfg, "target.a",
                            "target.handshake.thermal.from_potential computes the lattice "
                            "constant at the target's temperature: leave out target.a");
    if ((rc = cfg_ints(&to, "cells", 3, cells_def, CFG_RANGE(1, 10000), s->cells)) ||
        (rc = cfg_real(&to, "temperature", 0.0, CFG_GE(0), &s->temperature)) ||
        (rc = md_read_max_particles(&to, &s->max_particles)) ||
        (rc = impact_boundary_read(&to, b)))
        return rc;
    b->temperature = s->temperature;
    int ca_given;   /* from_potential: cluster.a defaults to a(T), known later */
    if ((rc = cfg_section_required(root, "cluster", &co)) ||
        (rc = cfg_enum(&co, "lattice", impact_lattices[s->tlat], impact_lattices, &s->clat)) ||
        (rc = cfg_string(&co, "element", s->telement, &s->celement)) ||
        (rc = s->ta > 0 ? cfg_real(&co, "a", s->ta, CFG_GT(0), &s->ca)
                        : cfg_real_opt(&co, "a", CFG_GT(0), &s->ca, &ca_given)) ||
        (rc = cfg_int(&co, "atoms", CFG_REQUIRED_INT, CFG_RANGE(1, 100000000), &s->natoms)) ||
        (rc = cfg_real(&co, "speed", 10.0, CFG_GE(0), &s->speed)) ||
        (rc = cfg_real(&co, "gap", 0.0, CFG_GE(0), &s->gap)))
        return rc;
    s->has_center = json_object_get(co.node, "center") != NULL;
    if (s->has_center) {
        static const double zero[3] = {0, 0, 0};
        if ((rc = cfg_reals(&co, "center", 3, zero, CFG_RANGE(-1, 1), s->center)))
            return rc;
    }
    if ((rc = cfg_close(&co)))
        return rc;
    /* target and cluster, before anything is built (also for resolve) */
    struct lattice tl = {impact_styles[s->tlat], s->ta, {0, 0, 0}, {{0}}};
    int ns = lattice_cell_sites(&tl);
    if (ns < 0)
        return err_nomem(root->cfg->err, "lattice sites");
    char what[160];
    snprintf(what, sizeof what, "%ld x %ld x %ld cells of %d sites and a cluster of %ld are",
             s->cells[0], s->cells[1], s->cells[2], ns, s->natoms);
    if ((rc = md_check_count(&to, "cells", (double)s->cells[0] * (double)s->cells[1] *
                                               (double)s->cells[2] * ns + (double)s->natoms,
                             s->max_particles, what)) ||
        (rc = cfg_close(&to)))
        return rc;
    /* the case's own default: the paper's 10 ps at 1 fs */
    struct md_settings def = md_settings_defaults, ms;
    def.steps = 10000;
    if ((rc = md_settings_read(root,
                               MD_KEY_TIMESTEP | MD_KEY_STEPS | MD_KEY_SKIN |
                                   MD_KEY_MAX_DISPLACEMENT,
                               &def, &ms)))
        return rc;
    s->dt = ms.timestep;
    s->steps = ms.steps;
    s->skin = ms.skin;
    s->maxdisp = ms.max_displacement;
    return 0;
}

static double nn_distance(enum lattice_style st, double a)
{
    struct lattice l = {st, a, {0, 0, 0}, {{0}}};
    return lattice_nn_distance(&l);
}

/* Whether the run is split into bricks (*halo, new) or not (NULL); every
 * boundary runs on bricks. */
static int plan_bricks(const struct case_common *common, const struct box *box, double range,
                       struct cfg *cfg, struct halo **halo)
{
    const struct parallel *par = common->par;
    *halo = NULL;
    if (!par || !par->mpi)
        return 0;
    return md_bricks_plan(par, &common->parallel, box, range, cfg, halo);
}

/* Build target + cluster; refuse what cannot work.  Under mpirun with
 * bricks each rank builds its own brick's target sites and cluster atoms,
 * with the ids of a serial build (target sites first, then the cluster). */
static int build(struct impact *c, const struct impact_spec *s, struct potential **potp,
                 struct cfg *cfg, const struct case_common *common)
{
    struct potential *pot = *potp;
    struct err *e = cfg->err;
    uint64_t seed = common->seed;
    struct particles *p = particles_create(1024);
    if (!p)
        return err_nomem(e, "particles");
    int rc = 0;
    struct cluster_cut cut = {0};
    struct lattice tl = {impact_styles[s->tlat], s->ta, {0, 0, 0}, {{0}}};
    int tt = particles_type_index(p, s->telement, element_mass(s->telement));
    int ct = particles_type_index(p, s->celement, element_mass(s->celement));
    int64_t next_id = 1;
    /* a rank of a brick run needs the whole target's extent (the box, the
     * layers, the surface) before it builds its own brick: a pass over
     * every site that stores none */
    c->ntarget = lattice_extent(&tl, s->cells, NULL, c->lo, c->hi, e);
    if (c->ntarget < 0) {
        particles_destroy(&p);
        return ERR_RUNTIME;
    }
    c->surface = c->hi[2];
    c->a = s->ta;
    /* the boundary needs a free interior, and a fixed layer a cutoff thick */
    struct impact_boundary *b = &c->bnd;
    double layer = b->fixed_thickness + b->damped_thickness;
    double wx = c->hi[0] - c->lo[0] - 2 * layer, wy = c->hi[1] - c->lo[1] - 2 * layer;
    double wz = c->hi[2] - c->lo[2] - layer;
    if (!b->ops->prepare && b->fixed_thickness < pot->cutoff) {
        rc = cfg_error_at(cfg, "target.fixed_thickness",
                          "%g Å is thinner than the potential cutoff %g Å: the damped atoms would "
                          "not see a complete crystal", b->fixed_thickness, pot->cutoff);
    } else if (wx <= 0 || wy <= 0 || wz <= 0) {
        rc = cfg_error_at(cfg, "target.cells",
                          "the target (%.1f x %.1f x %.1f Å) has no free interior inside its "
                          "%.1f Å of fixed and damped layers", c->hi[0] - c->lo[0],
                          c->hi[1] - c->lo[1], c->hi[2] - c->lo[2], layer);
    }
    if (!rc && cluster_cut_sphere(impact_styles[s->clat], s->ca, s->natoms,
                                  s->has_center ? s->center : NULL, &cut, e)) {
        char msg[ERR_MSG_MAX];
        snprintf(msg, sizeof msg, "%s", e->msg);
        rc = cfg_error_at(cfg, "cluster.atoms", "%s", msg);
    }
    if (!rc) {
        double width = 2 * cut.extent + nn_distance(impact_styles[s->clat], s->ca);
        double free_w = fmin(wx, wy);
        if (width >= free_w)
            rc = cfg_error_at(cfg, "cluster.atoms",
                              "a cluster of %ld atoms is %.1f Å across, as wide as or wider than "
                              "the free part of the target's top face (%.1f Å inside the fixed "
                              "and damped layers); enlarge target.cells",
                              s->natoms, width, free_w);
    }
    if (rc) {
        cluster_cut_free(&cut);
        particles_destroy(&p);
        return rc;
    }
    c->ncluster = cut.n;
    c->cluster_radius = cut.radius;
    memcpy(c->center_frac, cut.center, sizeof c->center_frac);
    /* place: centred over the top face, lowest atom `gap` above the surface */
    double gap = s->gap > 0 ? s->gap : pot->cutoff + 1.0;
    double zlow = INFINITY;
    for (long k = 0; k < cut.n; k++)
        zlow = fmin(zlow, cut.pos[k][2]);
    double cx = 0.5 * (c->lo[0] + c->hi[0]), cy = 0.5 * (c->lo[1] + c->hi[1]);
    double cz = c->surface + gap - zlow;
    c->speed = s->speed * 10.0;   /* km/s -> Å/ps */
    double vel[3] = {0, 0, -c->speed};
    struct box box = {0};
    for (int d = 0; d < 3; d++) {
        box.lo[d] = c->lo[d];
        box.hi[d] = d == 2 ? cz + 2 * c->cluster_radius : c->hi[d];
        box.bc[d] = BOUNDARY_FREE;
    }
    /* what the boundary owns (the handshake: its whole MPM side) and the
     * room its particles need, before the box is cut into bricks */
    b->a = s->ta;
    if (b->ops->prepare)
        rc = b->ops->prepare(b, c->lo, c->hi, p, tt, &box, pot, common->nthreads, cfg);
    /* bricks or not: each rank builds only its brick's atoms from here */
    struct halo *halo = NULL;
    double range = pot->cutoff + s->skin;
    if (rc || (rc = plan_bricks(common, &box, range, cfg, &halo))) {
        cluster_cut_free(&cut);
        particles_destroy(&p);
        return rc;
    }
    next_id = 1;
    rc = lattice_fill_where(&tl, s->cells, NULL, halo ? decomp_owns_point : NULL,
                            halo ? &halo->dc : NULL, p, tt, &next_id, e) < 0
             ? ERR_RUNTIME
             : 0;
    if (halo)
        rc = halo_adopt(halo, p, rc, e);
    /* the target's velocities, before the cluster joins (velocity_maxwell_split:
     * the serial draws by id on every rank count) */
    if (!rc && s->temperature > 0 && !(rc = potential_bind(pot, p, e)))
        rc = halo ? velocity_maxwell_split(p, s->temperature, seed, 1u, halo, e)
                  : velocity_maxwell(p, s->temperature, seed, 1u, e);
    for (long k = 0; !rc && k < cut.n; k++) {
        double x[3] = {cx + cut.pos[k][0], cy + cut.pos[k][1], cz + cut.pos[k][2]};
        if (halo && !decomp_owns(&halo->dc, x))
            continue;
        int i = particles_add(p, x, vel, ct, next_id + k);
        if (i < 0)
            rc = err_nomem(e, "cluster");
        else
            p->mask[i] |= IMPACT_GROUP_CLUSTER;
    }
    cluster_cut_free(&cut);
    if (halo)   /* counts the cluster atoms too; collective */
        rc = halo_adopt(halo, p, rc, e);
    /* the boundary's own particles (the handshake: the copies of regions
     * II and III; on bricks those in the rank's brick), counted too */
    if (!rc && b->ops->add_particles) {
        rc = b->ops->add_particles(b, &p, halo, e);
        if (halo)
            rc = halo_adopt(halo, p, rc, e);
    }
    if (!rc && halo) {
        md_adopt(&c->md, p, halo);   /* the md owns the halo from here */
        /* the impact puts the atoms unevenly: move the cuts when asked */
        if (common->parallel.balance == BALANCE_SHIFT)
            rc = halo_balance(halo, &box, p, range, e);
    } else if (!rc && common->par && common->par->mpi && common->par->size > 1 &&
               !b->ops->prepare) {
        p->par = common->par;   /* replicated data: each rank a slice of the forces */
    }
    if (rc) {
        particles_destroy(&p);
        if (c->md.halo)
            md_free(&c->md);
        else if (halo) {
            halo_free(halo);
            free(halo);
        }
        return rc;
    }
    *potp = NULL;   /* the md owns particles and potential from here on */
    rc = md_init(&c->md, p, &box, pot, s->dt, s->skin, common->nthreads, e);
    if (rc) {
        md_free(&c->md);
        return rc;
    }
    c->md.seed = seed;
    if (c->md.halo && common->parallel.balance_every > 0)
        halo_balance_schedule(c->md.halo, common->parallel.balance_every,
                              common->parallel.balance_threshold, 0);
    double m = p->mass[ct];
    c->impact_energy = 0.5 * m * c->speed * c->speed * UNITS_MVV2E * (double)c->ncluster;
    if (b->ops->setup && (rc = b->ops->setup(b, &c->md, c->lo, c->hi, e)))
        return rc;
    /* time step: the displacement rule for the projectile, then stability */
    rc = md_check_displacement(&c->md, nn_distance(impact_styles[s->tlat], s->ta), s->maxdisp, cfg,
                               "md.timestep");
    if (!rc)
        rc = md_check_timestep(&c->md, cfg, "md.timestep");
    return rc;
}

/* from_potential: the target at the potential's 0 K lattice constant
 * for the read (the layout checks and counts are those at a(T)); a
 * shallow read builds nothing and takes the middle of the bracket. */
static int lattice_constant_at_0K(struct impact_spec *s, const struct impact_boundary *b,
                                  struct potential *pot, struct cfg *cfg)
{
    const struct impact_from_potential *fp = b->from_potential;
    if (cfg->shallow)
        s->ta = 0.5 * (fp->a_min + fp->a_max);
    else if (impact_from_potential_a0(fp, pot, impact_styles[s->tlat], s->telement, &s->ta,
                                      cfg->err)) {
        char msg[ERR_MSG_MAX];
        snprintf(msg, sizeof msg, "%s", cfg->err->msg);
        return cfg_error_at(cfg, "target.handshake.thermal.from_potential", "%s", msg);
    }
    if (!(s->ca > 0))
        s->ca = s->ta;   /* cluster.a defaults to the target's */
    return 0;
}

/* What the second read of from_potential needs: the document as given
 * (`given`, taken before this read filled in its defaults; c owns it from
 * here), its directory, the run's settings. */
static int keep_document(struct impact *c, json_t *given, const struct cfg *cfg,
                         const struct case_common *common, const struct impact_spec *s)
{
    c->doc = given;
    c->base_dir = strdup(cfg->base_dir ? cfg->base_dir : ".");
    c->common = *common;
    c->common.title = NULL;   /* borrowed from the document */
    c->tlat = s->tlat;
    return c->base_dir ? 0 : err_nomem(cfg->err, "case directory");
}

static void impact_destroy(void *state);

/* The models of a case (the md, its analysis, the boundary). */
static void release_models(struct impact *c)
{
    impact_boundary_free(&c->bnd);
    if (c->md.p || c->md.halo)   /* a failed read may not have built it */
        md_free(&c->md);
    md_analysis_free(&c->an);
}

static int impact_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct impact_spec s;
    memset(&s, 0, sizeof s);
    struct impact_boundary bnd;
    memset(&bnd, 0, sizeof bnd);
    struct cfg_obj po;
    struct potential *pot = NULL;
    /* from_potential reads the document again at a(T): as it is given,
     * before this read fills in its defaults */
    json_t *given = NULL;
    if (!root->cfg->shallow &&
        impact_from_potential_given(json_object_get(root->node, "target")) &&
        !(given = json_deep_copy(root->node)))
        return err_nomem(root->cfg->err, "case document");
    int rc = read_spec(root, &s, &bnd);
    if (!rc)
        rc = cfg_section_required(root, "potential", &po);
    if (!rc)
        rc = potential_create(&po, &pot);
    if (!rc && bnd.from_potential)
        rc = lattice_constant_at_0K(&s, &bnd, pot, root->cfg);
    struct structure_params def = {impact_refs[s.tlat], CNA_FIXED, s.ta, 0, 0, 0, 0.15, 1};
    struct impact *c = rc ? NULL : calloc(1, sizeof *c);
    if (!rc && !c)
        rc = err_nomem(root->cfg->err, "impact case");
    json_t *structure = json_object_get(json_object_get(root->node, "analysis"), "structure");
    int reference_given = json_object_get(structure, "lattice_constant") != NULL;
    if (!rc)
        rc = md_analysis_read(root, &def, 100, &c->an);
    /* from_potential: the reference lattice constant of the structure
     * analysis defaults to target.a = a(T), unknown until the run: the
     * resolved case leaves it out, as it leaves out target.a (0 K stands
     * in here; the run's second read at a(T) fills it in) */
    structure = json_object_get(json_object_get(root->node, "analysis"), "structure");
    if (!rc && bnd.from_potential && !reference_given)
        json_object_del(structure, "lattice_constant");
    if (rc || root->cfg->shallow) {
        potential_destroy(&pot);
        impact_boundary_free(&bnd);
        if (c)
            md_analysis_free(&c->an);
        free(c);
        json_decref(given);
        return rc;
    }
    c->bnd = bnd;
    c->steps = s.steps;
    if (given)   /* c owns it from here */
        rc = keep_document(c, given, root->cfg, common, &s);
    if (!rc)
        rc = build(c, &s, &pot, root->cfg, common);
    if (!rc) {
        double q = 0.25 * s.ta;   /* crater grid a quarter cell off the lattice planes */
        struct md_analysis_opts o = {
            c->bnd.ops->exclude_mask ? c->bnd.ops->exclude_mask(&c->bnd) : 0,
            1, 1, c->surface,
            {0.5 * (c->lo[0] + c->hi[0]), 0.5 * (c->lo[1] + c->hi[1])},
            {c->lo[0] - q, c->lo[1] - q}, {c->hi[0] + q, c->hi[1] + q},
            s.ta,   /* columns of one cubic cell: two atoms of every (001) layer */
            /* half the (001) layer spacing: a/4 (fcc, bcc), a/8 (diamond) */
            s.tlat == 2 ? s.ta / 8.0 : s.ta / 4.0,
            1};
        rc = md_analysis_attach(&c->an, c->md.p, &o, common->nthreads, root->cfg->err);
    }
    if (rc) {
        /* build() hands the potential to the md (and NULLs pot) at md_init */
        potential_destroy(&pot);
        impact_destroy(c);
        return rc;
    }
    *state = c;
    return 0;
}

/* target.handshake.thermal.from_potential: a(T) and the constants at T by
 * type: elastic's computation (elastic_thermal.h) with the potential of
 * the case read at 0 K, then the case read again from its document with
 * target.a = a(T) and target.handshake.elastic = the constants: the run is
 * then the run with those numbers given (the structure analysis and the
 * cluster's lattice constant default to target.a as there).  c->at_T gets
 * the new case, and the computation's results for its metrics; c keeps
 * only that case. */
static int read_at_temperature(struct impact *c, struct run *run, struct err *e)
{
    const double G = UNITS_EVA3_TO_GPA;
    struct impact_from_potential *fp = c->bnd.from_potential;
    json_t *target = json_object_get(c->doc, "target");
    json_t *hs = json_object_get(target, "handshake");
    json_t *th = json_object_get(hs, "thermal");
    const char *element = json_string_value(json_object_get(target, "element"));
    int rc = impact_from_potential_compute(fp, c->md.pot, impact_styles[c->tlat], element,
                                           c->common.seed, c->common.nthreads, run, e);
    if (rc)
        return rc;
    json_t *el = json_pack("{s:f, s:f, s:f}", "c11", fp->out.c[0] * G, "c12", fp->out.c[1] * G,
                           "c44", fp->out.c[2] * G);
    if (!el || json_object_del(th, "from_potential") ||
        json_object_set_new(target, "a", json_real(fp->out.a)) ||
        json_object_set_new(hs, "elastic", el))
        return err_nomem(e, "case document at a(T)");
    /* the case at 0 K has done its part: its memory goes before the next */
    c->bnd.from_potential = NULL;
    release_models(c);
    /* the first read's cfg is gone: errors name the case type */
    struct cfg cfg = {"cluster_impact (from_potential)", NULL, e, c->base_dir, 0};
    struct cfg_obj root;
    void *state = NULL;
    if ((rc = cfg_root(&cfg, c->doc, &root)) || (rc = impact_read(&root, &c->common, &state))) {
        free(fp);
        return rc;
    }
    c->at_T = state;
    c->at_T->bnd.from_potential = fp;   /* for its metrics; it frees it */
    return 0;
}

/* --- the run on the engine (engine/sim.h) --------------------------------- */

/* The analysis of the current configuration: on bricks over the atoms of
 * every rank (md_analysis_bricks.h; the serial analysis on rank 0). */
static int analyse(struct impact *c, struct err *e)
{
    struct md *md = &c->md;
    return md->halo ? md_analysis_run_bricks(&c->an, md->halo, md->p, &md->box, md->time,
                                             md->timers, e)
                    : md_analysis_run(&c->an, md->p, &md->box, md->time, md->timers, e);
}

static int impact_begin(void *state, struct sim *s, struct err *e)
{
    struct impact *c = state;
    struct md *md = &c->md;
    struct run *run = s->run;
    int rc = md_output_begin(&c->out, run, md, e);
    if (rc)
        return rc;
    c->out.xyz_field = c->an.f_structure;
    if (s->restarted_from >= 0) {
        rc = md_output_resume(&c->out, run, c->restored_rows, c->nrestored, e);
        free(c->restored_rows);
        c->restored_rows = NULL;
        return rc;
    }
    run_log(run, "target %ld atoms (%ld fixed, %ld damped), cluster %ld atoms (cut radius %.2f Å), "
                 "%.2f keV at %.2f km/s",
            c->ntarget, c->bnd.nfixed, c->bnd.ndamped, c->ncluster, c->cluster_radius,
            c->impact_energy * 1e-3, c->speed / 10.0);
    rc = analyse(c, e);
    c->peak = c->an.displaced;
    c->peak_t = md->time;
    return rc;
}

static int impact_after_step(void *state, struct sim *s, struct err *e)
{
    struct impact *c = state;
    if (!md_analysis_due(&c->an, s->run, s->step, c->steps))
        return 0;
    int rc = analyse(c, e);
    if (!rc && c->an.displaced > c->peak) {
        c->peak = c->an.displaced;
        c->peak_t = c->md.time;
    }
    return rc;
}

static int impact_output(void *state, struct sim *s, unsigned due, struct err *e)
{
    struct impact *c = state;
    (void)due;   /* md_output_step reads the same schedule */
    return md_output_step(&c->out, s->run, &c->md, c->steps)
               ? err_set(e, ERR_RUNTIME, "step %ld: %s", s->step, c->out.err.msg)
               : 0;
}

/* The analysis row closest in time to t (-1: no rows). */
static long row_at(const struct md_analysis *a, double t)
{
    long best = -1;
    double d = INFINITY;
    for (long r = 0; r < a->nrows; r++) {
        double dr = fabs(md_analysis_row(a, r)[0] - t);
        if (dr < d) {
            d = dr;
            best = r;
        }
    }
    return best;
}

/* Column `name` of row r, NaN when either is missing. */
static double cell(const struct md_analysis *a, long r, const char *name)
{
    int k = md_analysis_column(a, name);
    return r >= 0 && k >= 0 ? md_analysis_row(a, r)[k] : NAN;
}

/* From the analysis series: stacking faults (stacking_faults.h), the
 * damage shape at the displaced peak and at the end (damage_shape.h), and
 * the largest crater volume. */
static void report_series_metrics(const struct md_analysis *a, double peak_t, struct result *r)
{
    int kh = md_analysis_column(a, "n_hcp"), kv = md_analysis_column(a, "crater_volume_A3");
    struct sf_burst b;
    stacking_faults_burst(a->rows, kh >= 0 ? a->rows + kh : a->rows, kh >= 0 ? a->nrows : 0,
                          a->ncols, STACKING_FAULTS_MIN_ATOMS, &b);
    result_metric(r, "hcp_peak", b.peak, "1");
    result_metric(r, "hcp_peak_time", b.peak_time, "ps");
    result_metric(r, "hcp_burst_time", b.burst_time, "ps");
    result_metric(r, "hcp_rise_time", b.rise_time, "ps");
    long rp = row_at(a, peak_t), rf = a->nrows - 1;
    result_metric(r, "damage_eig_ratio_at_peak", cell(a, rp, "damage_eig_ratio"), "1");
    result_metric(r, "damage_axis_deg_at_peak", cell(a, rp, "damage_axis_deg"), "deg");
    result_metric(r, "damage_extent_ratio_at_peak", cell(a, rp, "damage_extent_ratio"), "1");
    result_metric(r, "damage_eig_ratio_final", cell(a, rf, "damage_eig_ratio"), "1");
    result_metric(r, "damage_axis_deg_final", cell(a, rf, "damage_axis_deg"), "deg");
    result_metric(r, "damage_extent_ratio_final", cell(a, rf, "damage_extent_ratio"), "1");
    double vmax = 0, tv = NAN;
    for (long q = 0; kv >= 0 && q < a->nrows; q++)
        if (md_analysis_row(a, q)[kv] > vmax) {
            vmax = md_analysis_row(a, q)[kv];
            tv = md_analysis_row(a, q)[0];
        }
    result_metric(r, "crater_volume_peak", vmax, "Å^3");
    result_metric(r, "crater_volume_peak_time", tv, "ps");
}

static int impact_report(void *state, struct sim *s, int run_rc, struct err *e)
{
    struct impact *c = state;
    struct md *md = &c->md;
    struct run *run = s->run;
    if (run_rc == ERR_DIVERGED)
        md_output_snapshot(&c->out, run, md);
    long peak = c->peak;
    double peak_t = c->peak_t;
    double e0 = s->e0[c->md_index].total;
    struct result *r = &run->result;
    double etot = md->last.energy + md_kinetic_energy(md);
    result_metric(r, "atoms", (double)md_natoms(md), "1");
    result_metric(r, "target_atoms", (double)c->ntarget, "1");
    result_metric(r, "cluster_atoms", (double)c->ncluster, "1");
    result_metric(r, "cluster_radius", c->cluster_radius, "Å");
    result_metric(r, "impact_speed", c->speed / 10.0, "km/s");
    result_metric(r, "impact_energy", c->impact_energy * 1e-3, "keV");
    result_metric(r, "impact_energy_per_atom", c->impact_energy / (double)c->ncluster, "eV");
    result_metric(r, "fixed_atoms", (double)c->bnd.nfixed, "1");
    result_metric(r, "damped_atoms", (double)c->bnd.ndamped, "1");
    result_metric(r, "time", md->time, "ps");
    result_metric(r, "displaced_peak", (double)peak, "1");
    result_metric(r, "displaced_peak_time", peak_t, "ps");
    result_metric(r, "displaced_final", (double)c->an.displaced, "1");
    result_metric(r, "displaced_final_over_peak", peak > 0 ? (double)c->an.displaced / peak : 0.0, "1");
    result_metric(r, "hcp_final", (double)c->an.counts[STRUCT_HCP], "1");
    result_metric(r, "sputtered_atoms", (double)c->an.sputter.atoms, "1");
    result_metric(r, "sputtered_clusters", (double)c->an.sputter.clusters, "1");
    result_metric(r, "sputtered_monomers", (double)c->an.sputter.monomers, "1");
    result_metric(r, "sputtered_largest", (double)c->an.sputter.largest, "1");
    const struct crater_stats *cs = &c->an.crater;
    double w100 = 0.5 * (cs->extent[0] + cs->extent[1]), w110 = 0.5 * (cs->extent[2] + cs->extent[3]);
    result_metric(r, "crater_depth", cs->depth, "Å");
    result_metric(r, "crater_volume", cs->volume, "Å^3");
    result_metric(r, "crater_extent_100", w100, "Å");
    result_metric(r, "crater_extent_110", w110, "Å");
    result_metric(r, "crater_shape_110_over_100", w100 > 0 ? w110 / w100 : 0.0, "1");
    result_metric(r, "rim_height", cs->rim, "Å");
    report_series_metrics(&c->an, peak_t, r);
    result_metric(r, "energy_absorbed", e0 - etot, "eV");
    result_metric(r, "temperature", md_temperature(md), "K");
    if (c->bnd.ops->report)
        c->bnd.ops->report(&c->bnd, r);
    run_log(run, "displaced atoms: peak %ld at %.2f ps, final %ld; sputtered %ld atoms in %ld "
                 "groups; crater %.1f Å deep, %.1f x %.1f Å ([100] x [110])",
            peak, peak_t, c->an.displaced, c->an.sputter.atoms, c->an.sputter.clusters, cs->depth,
            w100, w110);
    if (md->halo)
        md_output_decomposition(run, md);
    int rc2 = md_analysis_finish(&c->an, run, e);
    int rc3 = md_output_end(&c->out, run, e);
    rc2 = rc2 ? rc2 : rc3;
    /* bricks: rank 0 wrote; every rank returns its verdict */
    return md->halo ? halo_agree(md->halo, rc2, e) : rc2;
}

/* The analysis' latest results and series, the peak, the thermo rows. */
static int impact_checkpoint_write(void *state, struct ckpt *ck, struct err *e)
{
    struct impact *c = state;
    const struct md_analysis *a = &c->an;
    long latest[2] = {a->displaced, a->counted};
    int rc = ckpt_put_long(ck, "displaced_peak", c->peak);
    if (!rc) rc = ckpt_put_double(ck, "displaced_peak_time", c->peak_t);
    if (!rc) rc = ckpt_put_bytes(ck, "analysis_counts", a->counts, (long)sizeof a->counts);
    if (!rc) rc = ckpt_put_bytes(ck, "analysis_latest", latest, (long)sizeof latest);
    if (!rc) rc = ckpt_put_bytes(ck, "analysis_sputter", &a->sputter, (long)sizeof a->sputter);
    if (!rc) rc = ckpt_put_bytes(ck, "analysis_crater", &a->crater, (long)sizeof a->crater);
    if (!rc) rc = ckpt_put_doubles(ck, "analysis_rows", a->rows, a->nrows * a->ncols);
    if (!rc) rc = ckpt_put_doubles(ck, "thermo_rows", c->out.series, c->out.nrows * MD_THERMO_COLS);
    return rc;
}

static int impact_checkpoint_read(void *state, struct ckpt *ck, struct err *e)
{
    struct impact *c = state;
    struct md_analysis *a = &c->an;
    long latest[2];
    int rc = ckpt_get_long(ck, "displaced_peak", &c->peak);
    if (!rc) rc = ckpt_get_double(ck, "displaced_peak_time", &c->peak_t);
    if (!rc) rc = ckpt_get_bytes(ck, "analysis_counts", a->counts, (long)sizeof a->counts);
    if (!rc) rc = ckpt_get_bytes(ck, "analysis_latest", latest, (long)sizeof latest);
    if (!rc) rc = ckpt_get_bytes(ck, "analysis_sputter", &a->sputter, (long)sizeof a->sputter);
    if (!rc) rc = ckpt_get_bytes(ck, "analysis_crater", &a->crater, (long)sizeof a->crater);
    a->displaced = latest[0];
    a->counted = latest[1];
    if (!rc)
        rc = ckpt_get_rows(ck, "analysis_rows", a->ncols, &a->rows, &a->nrows);
    a->caprows = a->nrows;
    if (!rc)
        rc = ckpt_get_rows(ck, "thermo_rows", MD_THERMO_COLS, &c->restored_rows, &c->nrestored);
    return rc;
}

static const struct sim_case_ops impact_case_ops = {
    .begin = impact_begin,
    .after_step = impact_after_step,
    .output = impact_output,
    .report = impact_report,
    .checkpoint_write = impact_checkpoint_write,
    .checkpoint_read = impact_checkpoint_read,
};

static int impact_run(void *state, struct run *run, struct err *e)
{
    struct impact *c = state;
    if (c->doc) {   /* from_potential: the run is that of the case read at a(T) */
        int rc = read_at_temperature(c, run, e);
        if (rc)
            return rc;
        c = c->at_T;
    }
    c->md.timers = &run->timers;
    /* the boundary's pre_step before the md's drift, its step after the
     * md's kick: the boundary model first */
    c->bmodel = (struct impact_boundary_model){&c->bnd, &c->md};
    c->model = (struct md_model){.md = &c->md, .peratom_always = c->bnd.peratom};
    struct sim s;
    sim_init(&s, run, c->steps, c->md.dt);
    s.case_ops = &impact_case_ops;
    s.case_state = c;
    int rc = sim_add_model(&s,
                           c->bnd.ops->stateless || c->bnd.ops->checkpoint_write
                               ? &sim_model_impact_boundary
                               : &sim_model_impact_boundary_stateful,
                           &c->bmodel, e);
    c->md_index = s.nmodels;
    if (!rc)
        rc = sim_add_model(&s, &sim_model_md, &c->model, e);
    return rc ? rc : sim_run(&s, run->opt.restart, e);
}

static void impact_destroy(void *state)
{
    struct impact *c = state;
    if (!c)
        return;
    impact_destroy(c->at_T);
    release_models(c);
    free(c->restored_rows);
    json_decref(c->doc);
    free(c->base_dir);
    free(c);
}

static long impact_particles(const void *state)
{
    const struct impact *c = state;
    if (c && c->at_T)
        c = c->at_T;
    return c && c->md.p ? md_natoms(&c->md) : 0;
}

const struct case_type impact_case_type = {
    "cluster_impact", "a cluster hitting a crystal surface: damage, sputtering, crater",
    impact_read, impact_run, impact_destroy, impact_particles, NULL,
    .checkpoints = 1,
    .decomposes = 1,
    .balances = 1,
};
