/* handshake_impact: the MPM/MD handshake around a cluster-impact target
 * (Guo & Yang 2005, section 3.2, Fig. 12; see handshake_impact.h). */
#include "scenarios/handshake_impact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/halo.h"
#include "core/units.h"
#include "couple/handshake.h"
#include "couple/handshake_thermal.h"
#include "output/result.h"
#include "scenarios/handshake_record.h"
#include "scenarios/impact_from_potential.h"

struct hs_impact {
    double mpm, regions[3], cell, fine, layer;   /* lattice constants */
    long levels;
    int coarsen;                                 /* direction bits x 1, y 2, z 4 */
    enum hs_lattice lattice;                     /* target.lattice */
    struct handshake hs;
    int built;
    struct handshake_energy e0;                  /* when the run starts */
    /* finite temperature (target.handshake.thermal, handshake_thermal.h) */
    int thermal;                                 /* the section is given */
    struct hs_thermal bath;
    double c_user[3];                            /* GPa: MPM constants (0: the potential's at 0 K) */
    double account0;                             /* the energy account when the run starts */
    double zeta0;                                /* diamond's zeta at 0 K (0: fcc, bcc) */
};

/* The energy account of the boundary (eV): the MD atoms of the target and
 * cluster (kinetic, and potential above the perfect crystal), the MPM
 * (kinetic and strain of every point), and at a temperature the heat the
 * bath took out and the fine-scale energy of the MD copies of region II
 * (atoms then): each copy's kinetic energy relative to its point,
 * m |v - v_p|^2 / 2, and its potential energy above the perfect crystal
 * less its point's strain energy, so that the coarse field of region II
 * is counted once (as points).  What this account loses over a run is
 * energy that vanished in the coupling. */
static double energy_account(const struct hs_impact *h, const struct handshake_energy *en,
                             double *fine_II)
{
    double f = 0;
    if (h->thermal) {
        const struct handshake *hs = &h->hs;
        const struct particles *p = hs->md->p;
        for (long k = 0; k < hs->nlink; k++) {
            int i = hs->link_md[k];
            if (!(p->mask[i] & HS_MASK_II))
                continue;
            /* the point's velocity and strain energy (its row: on bricks
             * the point may be on another rank) */
            const double *row = hs->link_row + HS_LINK_ROW * k;
            double w = 0;
            for (int d = 0; d < 3; d++) {
                double dv = p->v[3 * i + d] - row[3 + d];
                w += dv * dv;
            }
            f += 0.5 * p->mass[p->type[i]] * UNITS_MVV2E * w + p->pe[i] - hs->cr.pe_ref -
                 row[6];
        }
    }
    /* bricks: each rank's copies (collective; the bath's heat is already
     * the same on every rank) */
    if (h->thermal && h->hs.md->halo)
        halo_sum(h->hs.md->halo, &f, 1);
    if (fine_II)
        *fine_II = f;
    return en->total + f + (h->thermal ? h->bath.heat : 0);
}

static const char *const coarsen_names[] = {"x", "y", "xy", "z", "xz", "yz", "xyz", NULL};

int handshake_impact_read(struct cfg_obj *t, struct impact_boundary *b)
{
    struct cfg *cfg = t->cfg;
    /* lattice, a and temperature are read before the boundary */
    json_t *lat = json_object_get(t->node, "lattice");
    int lattice = HS_LATTICE_FCC;
    if (json_is_string(lat)) {
        for (lattice = 0; hs_lattice_names[lattice]; lattice++)
            if (strcmp(json_string_value(lat), hs_lattice_names[lattice]) == 0)
                break;
        if (!hs_lattice_names[lattice])
            return cfg_error_at(cfg, "target.lattice",
                                "boundary 'handshake' needs a cubic target with its cube axes "
                                "along x, y, z (fcc, bcc or diamond: the MPM is cubic elastic "
                                "with regions II and III on the lattice sites), not '%s'",
                                json_string_value(lat));
    }
    double temp = json_number_value(json_object_get(t->node, "temperature"));
    json_t *hsn = json_object_get(t->node, "handshake");
    int thermal = json_is_object(hsn) && json_object_get(hsn, "thermal") != NULL;
    if (temp > 0 && !thermal)
        return cfg_error_at(cfg, "target.temperature",
                            "boundary 'handshake' runs at 0 K only without "
                            "target.handshake.thermal (the material points are not "
                            "thermalised), not %g K",
                            temp);
    struct hs_impact *h = calloc(1, sizeof *h);
    if (!h)
        return err_nomem(cfg->err, "handshake boundary");
    b->data = h;   /* freed by handshake_impact_destroy, also on errors */
    h->lattice = (enum hs_lattice)lattice;
    static const double regions_def[3] = {2, 2, 2};
    int ci, rc;
    struct cfg_obj o;
    if ((rc = cfg_section(t, "handshake", &o)) ||
        (rc = cfg_real(&o, "mpm", 16, CFG_GT(0), &h->mpm)) ||
        (rc = cfg_reals(&o, "regions", 3, regions_def, CFG_GT(0), h->regions)) ||
        (rc = cfg_real(&o, "cell", 1, CFG_GT(0), &h->cell)) ||
        (rc = cfg_real(&o, "fine", 6, CFG_GE(0), &h->fine)) ||
        (rc = cfg_int(&o, "levels", 2, CFG_RANGE(0, MPM_MAX_LEVELS), &h->levels)) ||
        (rc = cfg_enum(&o, "coarsen", "xyz", coarsen_names, &ci)) ||
        (rc = cfg_real(&o, "layer", 4, CFG_GT(0), &h->layer)))
        return rc;
    h->coarsen = ci + 1;
    /* finite temperature: the bath on region II and the MPM's constants at T */
    h->thermal = thermal;
    h->bath.temperature = temp;
    struct cfg_obj th, el;
    long seed = 1;
    /* read also when absent (its defaults are listed); given, it switches
     * the bath on */
    if ((rc = cfg_section(&o, "thermal", &th)) ||
        (rc = cfg_real(&th, "damping_time", HS_THERMAL_DAMPING_TIME, CFG_GE(0),
                       &h->bath.damping_time)) ||
        (rc = cfg_real(&th, "coarse_cell", HS_THERMAL_COARSE_CELL, CFG_GE(0),
                       &h->bath.coarse_cell)) ||
        (rc = cfg_int(&th, "seed", 1, CFG_GE(0), &seed)) ||
        (rc = impact_from_potential_read(&th, temp, &b->from_potential)) ||
        (rc = cfg_close(&th)))
        return rc;
    h->bath.seed = (uint64_t)seed;
    if ((rc = cfg_section(&o, "elastic", &el)) ||
        (rc = cfg_real(&el, "c11", 0, CFG_GE(0), &h->c_user[0])) ||
        (rc = cfg_real(&el, "c12", 0, CFG_GE(0), &h->c_user[1])) ||
        (rc = cfg_real(&el, "c44", 0, CFG_GE(0), &h->c_user[2])) || (rc = cfg_close(&el)) ||
        (rc = cfg_close(&o)))
        return rc;
    int given = (h->c_user[0] > 0) + (h->c_user[1] > 0) + (h->c_user[2] > 0);
    if (given != 0 && given != 3)
        return cfg_error_at(cfg, "target.handshake.elastic",
                            "give all of c11, c12, c44 or none (none: the potential's at 0 K)");
    if (b->from_potential && given != 0)
        return cfg_error_at(cfg, "target.handshake.elastic",
                            "target.handshake.thermal.from_potential computes the elastic "
                            "constants at %g K: leave out c11, c12 and c44",
                            temp);
    if (temp > 0 && given == 0 && !b->from_potential)
        return cfg_error_at(cfg, "target.handshake.elastic",
                            "a target at %g K needs the MPM's elastic constants at that "
                            "temperature: give c11, c12 and c44 (the output of type: elastic), "
                            "or thermal.from_potential to compute them here",
                            temp);
    b->peratom = 1;   /* region I gives the MPM its virial stress every step */
    return 0;
}

/* Layout refusals name the key under target.handshake. */
static const char *const key_path[HS_KEY_COUNT] = {
    "target.handshake.regions", "target.handshake.cell",  "target.handshake.fine",
    "target.handshake.levels",  "target.handshake.layer", "target.handshake.mpm",
    "target.cells"};

/* The target is [lo, hi] (its atoms' positions, from the case's pass over
 * every site: the same on every rank of a brick run), of atom type `type`
 * in p's type table.  Builds the whole MPM side; the MD copies join in
 * handshake_impact_add_particles. */
int handshake_impact_prepare(struct impact_boundary *b, const double lo[3], const double hi[3],
                             const struct particles *p, int type, struct box *box,
                             struct potential *pot, int nthreads, struct cfg *cfg)
{
    struct hs_impact *h = b->data;
    struct err *e = cfg->err;
    if (type < 0 || !(lo[0] <= hi[0]))
        return cfg_error_at(cfg, "target.cells", "boundary 'handshake': the target has no atoms");
    struct handshake_crystal cr;
    double a0, a = b->a;
    int rc = handshake_crystal_of_lattice(pot, h->lattice, p->type_name[type], 0.9 * a, 1.1 * a,
                                          &cr, &a0, e);
    if (rc) {
        char msg[ERR_MSG_MAX];
        snprintf(msg, sizeof msg, "%s", e->msg);
        return cfg_error_at(cfg, "target.a", "boundary 'handshake': %s", msg);
    }
    /* the MPM is stress-free at its sites: the MD must start so too (at a
     * temperature target.a is a(T), which only the user knows: type: elastic) */
    if (h->bath.temperature <= 0 && fabs(a / a0 - 1) > 1e-3)
        return cfg_error_at(cfg, "target.a",
                            "boundary 'handshake' needs the target at the potential's 0 K "
                            "lattice constant %.5f Å, not %g Å: the MPM is stress-free at its "
                            "lattice sites",
                            a0, a);
    cr.type = type;
    cr.mass = p->mass[type];
    h->zeta0 = cr.zeta;
    /* at a temperature target.a is a(T): diamond's copies of region III
     * take the internal shift of the crystal at that a, as in
     * handshake_thermal (handshake_crystal_zeta_at; 0 for fcc and bcc) */
    if (h->bath.temperature > 0 &&
        (rc = handshake_crystal_zeta_at(pot, h->lattice, &cr, a, &cr.zeta, e))) {
        char msg[ERR_MSG_MAX];
        snprintf(msg, sizeof msg, "%s", e->msg);
        return cfg_error_at(cfg, "target.a", "boundary 'handshake': %s", msg);
    }
    if (h->c_user[0] > 0) {
        cr.c11 = h->c_user[0] / UNITS_EVA3_TO_GPA;
        cr.c12 = h->c_user[1] / UNITS_EVA3_TO_GPA;
        cr.c44 = h->c_user[2] / UNITS_EVA3_TO_GPA;
    }
    struct handshake_layout L;
    memset(&L, 0, sizeof L);
    L.lattice = h->lattice;
    L.a = a;
    /* the MD box's faces lie between (100) planes of sites, as far from
     * the outermost sites as the grid planes from the sites */
    const double off = hs_lattice_offset(h->lattice) * a;
    for (int d = 0; d < 3; d++) {
        L.lat_origin[d] = lo[d];
        L.md_lo[d] = lo[d] - off;
        L.md_hi[d] = hi[d] + off;
        L.dom_lo[d] = L.mat_lo[d] = L.md_lo[d] - h->mpm * a;
        /* the top (+z) is the free surface: no MPM above it */
        L.dom_hi[d] = L.mat_hi[d] = d == 2 ? L.md_hi[d] : L.md_hi[d] + h->mpm * a;
        L.w[d] = h->regions[d] * a;
        L.face[2 * d] = L.face[2 * d + 1] = MPM_FACE_FIXED;
    }
    L.face[5] = MPM_FACE_FREE;
    if (h->thermal) {
        /* at a temperature the top edge atoms of region I (grid particles)
         * may rise above the surface plane: empty cells above the free
         * top, one coarsest cell, give them room (as the bar's loaded end) */
        double margin = h->cell * a;
        if (h->coarsen & 4)
            for (long l = 0; l < h->levels; l++)
                margin *= 2;
        L.dom_hi[2] += margin;
    }
    L.h = h->cell * a;
    L.fine = h->fine * a;
    L.nlevels = (int)h->levels;
    L.coarsen = (unsigned)h->coarsen;
    L.layer = h->layer * a;
    enum hs_layout_key key;
    char why[512];
    if (handshake_layout_check(&L, pot->cutoff, &key, why, sizeof why))
        return cfg_error_at(cfg, key_path[key], "%s", why);
    rc = handshake_build_mpm(&h->hs, &L, &cr, nthreads, e);
    h->built = 1;   /* handshake_free also undoes a partial build */
    if (rc)
        return rc;
    /* room for the copies of regions II and III below and beside the target */
    double shell = L.w[1] + L.w[2];
    for (int d = 0; d < 3; d++) {
        box->lo[d] = fmin(box->lo[d], L.md_lo[d] - shell);
        if (d < 2)
            box->hi[d] = fmax(box->hi[d], L.md_hi[d] + shell);
    }
    return 0;
}

int handshake_impact_add_particles(struct impact_boundary *b, struct particles **p,
                                   const struct halo *halo, struct err *e)
{
    struct hs_impact *h = b->data;
    return handshake_add_particles(&h->hs, p, halo, e);
}

int handshake_impact_setup(struct impact_boundary *b, struct md *md, const double lo[3],
                           const double hi[3], struct err *e)
{
    (void)lo;
    (void)hi;
    struct hs_impact *h = b->data;
    int rc = handshake_connect(&h->hs, md, e);
    if (rc)
        return rc;
    if (h->thermal) {
        double T = h->bath.temperature;
        /* the target's Maxwell-Boltzmann velocities at T become 2T: a
         * perfect lattice started at 2T settles at T (equipartition) */
        struct particles *p = md->p;
        for (int i = 0; i < p->n_owned; i++)
            if (!(p->mask[i] & (IMPACT_GROUP_CLUSTER | HS_MASK_II | HS_MASK_III)))
                for (int d = 0; d < 3; d++)
                    p->v[3 * i + d] *= sqrt(2.0);
        hs_thermal_attach(&h->hs, &h->bath, 2 * T);
    }
    handshake_energy(&h->hs, &h->e0);
    h->account0 = energy_account(h, &h->e0, NULL);
    return 0;
}

/* Before every md_step: region I at t to the MPM, the MPM to t + dt, the
 * copies of regions II and III to where the MPM put them (handshake.h). */
int handshake_impact_pre_step(struct impact_boundary *b, struct md *md, struct err *e)
{
    struct hs_impact *h = b->data;
    h->hs.mpm.timers = md->timers;
    int rc = handshake_advance_mpm(&h->hs, e);
    if (!rc) {
        h->hs.step++;
        h->hs.time += h->hs.md->dt;
    }
    return rc;
}

uint32_t handshake_impact_exclude(const struct impact_boundary *b)
{
    (void)b;
    return HS_MASK_II | HS_MASK_III;   /* the copies: material points, not atoms */
}

void handshake_impact_report(const struct impact_boundary *b, struct result *r)
{
    const struct hs_impact *h = b->data;
    if (!h || !h->built)
        return;
    const struct handshake *hs = &h->hs;
    const struct handshake_layout *L = &hs->lay;
    struct handshake_energy en;
    handshake_energy(hs, &en);
    double vd = 1, vb = 1;
    for (int d = 0; d < 3; d++) {
        vd *= L->mat_hi[d] - L->mat_lo[d];
        vb *= L->md_hi[d] - L->md_lo[d];
    }
    result_metric(r, "mpm_points", (double)hs->npoints, "1");
    handshake_record_parallel(hs, r);   /* bricks: points per rank (collective) */
    result_metric(r, "mpm_nodes", (double)hs->mpm.grid.nnodes, "1");
    result_metric(r, "atoms_region_I", (double)hs->counts[HS_I], "1");
    result_metric(r, "copies_region_II_III", (double)hs->ncopies, "1");
    result_metric(r, "atoms_replaced", (vd - vb) / hs->omega0, "1");
    result_metric(r, "mpm_energy", en.mpm_kinetic + en.mpm_strain, "eV");
    result_metric(r, "mpm_kinetic_energy", en.mpm_kinetic, "eV");
    /* MD atoms (kinetic + potential above the perfect crystal) + MPM */
    result_metric(r, "coupled_energy_initial", h->e0.total, "eV");
    result_metric(r, "coupled_energy_final", en.total, "eV");
    result_metric(r, "c11_mpm", hs->cr.c11 * UNITS_EVA3_TO_GPA, "GPa");
    result_metric(r, "kleinman_zeta", h->zeta0, "1");
    result_metric(r, "kleinman_zeta_mpm", hs->cr.zeta, "1");   /* at a(T) at a temperature */
    result_metric(r, "c12_mpm", hs->cr.c12 * UNITS_EVA3_TO_GPA, "GPa");
    result_metric(r, "c44_mpm", hs->cr.c44 * UNITS_EVA3_TO_GPA, "GPa");
    double fine_II;
    double acc = energy_account(h, &en, &fine_II);
    result_metric(r, "energy_account_initial", h->account0, "eV");
    result_metric(r, "energy_account_final", acc, "eV");
    if (h->thermal) {
        double T;
        hs_thermal_group(hs, 0, HS_MASK_II | HS_MASK_III | HS_MASK_FIXED | IMPACT_GROUP_CLUSTER,
                         NULL, &T, NULL);
        result_metric(r, "bath_heat", h->bath.heat, "eV");
        result_metric(r, "bath_damping_time", h->bath.damping_time, "ps");
        result_metric(r, "bath_coarse_cell", h->bath.coarse_cell, "1");
        result_metric(r, "region_II_fine_energy", fine_II, "eV");
        result_metric(r, "target_temperature_final", T, "K");
        result_metric(r, "lattice_constant_T", hs->lay.a, "Å");
        result_metric(r, "from_potential", b->from_potential != NULL, "1");
        if (b->from_potential)   /* what the computation gave, with its errors */
            elastic_thermal_report(&b->from_potential->out, &b->from_potential->set, r);
    }
}

void handshake_impact_destroy(struct impact_boundary *b)
{
    struct hs_impact *h = b->data;
    if (!h)
        return;
    if (h->built)
        handshake_free(&h->hs);
    free(h);
    b->data = NULL;
}

int handshake_impact_checkpoint_write(const struct impact_boundary *b, struct ckpt *ck,
                                      const char *group)
{
    const struct hs_impact *h = b->data;
    return handshake_checkpoint_write(&h->hs, ck, group);
}

int handshake_impact_checkpoint_read(struct impact_boundary *b, struct ckpt *ck, const char *group)
{
    struct hs_impact *h = b->data;
    return handshake_checkpoint_read(&h->hs, ck, group);
}

int handshake_impact_checkpoint_write_part(const struct impact_boundary *b, struct ckpt *ck,
                                           const char *group)
{
    const struct hs_impact *h = b->data;
    return handshake_checkpoint_write_part(&h->hs, ck, group);
}

int handshake_impact_checkpoint_collect(struct impact_boundary *b, struct err *e)
{
    struct hs_impact *h = b->data;
    return handshake_checkpoint_collect(&h->hs, e);
}

void handshake_impact_checkpoint_sync(struct impact_boundary *b)
{
    struct hs_impact *h = b->data;
    handshake_checkpoint_sync(&h->hs);
}
