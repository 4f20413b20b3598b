/*
 * structure_case: classify the local crystalline order of a configuration
 * (`type: structure`) -- a crystal built here, or a LAMMPS data or extended
 * XYZ file written by anything (an MD run, a DPD run at its coarse lattice
 * constant, another code).
 *
 *   system:   see md_system.h (lattice | read_data | read_xyz, boundary, ...)
 *   analysis:
 *     structure: {reference, method, lattice_constant, cutoff, surface_offset}
 *     repeat: 1          classify this many times (timing; the answer is the same)
 *   output: {...}       one HDF5 snapshot with the per-atom field `structure`
 *
 * Metrics: atoms, n_<class> and fraction_<class> for every class,
 * displaced, cna_us_per_atom (median wall time of one classification per
 * atom, µs) and cna_cpu_us_per_atom (the same in process CPU time, which a
 * busy shared machine disturbs less).
 */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "analysis/structure.h"
#include "core/timers.h"
#include "scenarios/case_type.h"
#include "input/md_system.h"

struct structure_case {
    struct particles *p;
    struct box box;
    struct structure_params sp;
    long repeat;
    int nthreads;
};

static int structure_read(struct cfg_obj *root, const struct case_common *common, void **state)
{
    struct particles *p = NULL;
    struct box box = {0};
    struct md_system_info info;
    int rc = md_system_read(root, common->seed, &p, &box, &info);
    if (rc)
        return rc;
    /* defaults from the lattice when the system is built here */
    struct structure_params def = {STRUCT_REF_FCC, CNA_FIXED, 0, 0, 0, 0, 0.15, 1};
    if (info.from_lattice) {
        def.a = info.lattice.a;
        switch (info.lattice.style) {
        case LATTICE_BCC: def.ref = STRUCT_REF_BCC; break;
        case LATTICE_DIAMOND: def.ref = STRUCT_REF_DIAMOND; break;
        case LATTICE_HCP: def.ref = STRUCT_REF_HCP; break;
        default: def.ref = STRUCT_REF_FCC; break;
        }
    }
    struct cfg_obj ao, so;
    struct structure_params sp;
    long repeat;
    if ((rc = cfg_section(root, "analysis", &ao)) || (rc = cfg_section(&ao, "structure", &so)) ||
        (rc = structure_params_read(&so, &def, &sp)) || (rc = cfg_close(&so)) ||
        (rc = cfg_int(&ao, "repeat", 1, CFG_RANGE(1, 1000), &repeat)) || (rc = cfg_close(&ao))) {
        particles_destroy(&p);
        return rc;
    }
    if (root->cfg->shallow)
        return 0;
    struct structure_case *c = calloc(1, sizeof *c);
    if (!c) {
        particles_destroy(&p);
        return err_nomem(root->cfg->err, "structure case");
    }
    c->p = p;
    c->box = box;
    c->sp = sp;
    c->sp.nthreads = common->nthreads;
    c->repeat = repeat;
    *state = c;
    return 0;
}

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int structure_run(void *state, struct run *run, struct err *e)
{
    struct structure_case *c = state;
    struct particles *p = c->p;
    int n = p->n_owned;
    int *cls = malloc((size_t)(n + 1) * sizeof *cls);
    double *times = malloc((size_t)c->repeat * sizeof *times);
    double *cpu = malloc((size_t)c->repeat * sizeof *cpu);
    int fidx = particles_add_field(p, "structure", 1, 0, e);
    if (!cls || !times || !cpu || fidx < 0) {
        free(cls);
        free(times);
        free(cpu);
        return fidx < 0 ? ERR_RUNTIME : err_nomem(e, "structure classes");
    }
    struct frame fr = {0};
    int rc = 0;
    timer_start(&run->timers, TIMER_LOOP);
    for (long r = 0; r < c->repeat && !rc; r++) {
        double t0 = timers_now(), c0 = cpu_seconds();
        timer_start(&run->timers, TIMER_ANALYSIS);
        rc = structure_classify_particles(&c->sp, p, &c->box, &fr, cls, e);
        timer_stop(&run->timers, TIMER_ANALYSIS);
        times[r] = timers_now() - t0;
        cpu[r] = cpu_seconds() - c0;
    }
    timer_stop(&run->timers, TIMER_LOOP);
    if (!rc) {
        long counts[STRUCT_NCLASSES];
        structure_count(cls, n, NULL, counts);
        double *f = particles_field(p, fidx);
        long displaced = 0;
        for (int i = 0; i < n; i++) {
            f[i] = cls[i];
            displaced += structure_is_displaced(c->sp.ref, cls[i]);
        }
        qsort(times, (size_t)c->repeat, sizeof *times, by_value);
        qsort(cpu, (size_t)c->repeat, sizeof *cpu, by_value);
        struct result *res = &run->result;
        result_metric(res, "atoms", n, "1");
        for (int k = 0; k < STRUCT_NCLASSES; k++) {
            char name[48];
            snprintf(name, sizeof name, "n_%s", structure_class_names[k]);
            result_metric(res, name, (double)counts[k], "1");
            snprintf(name, sizeof name, "fraction_%s", structure_class_names[k]);
            result_metric(res, name, n > 0 ? (double)counts[k] / n : 0.0, "1");
        }
        result_metric(res, "displaced", (double)displaced, "1");
        result_metric(res, "cutoff", c->sp.cutoff, "Å");
        result_metric(res, "cna_us_per_atom", n > 0 ? 1e6 * times[c->repeat / 2] / n : 0.0, "us");
        result_metric(res, "cna_cpu_us_per_atom", n > 0 ? 1e6 * cpu[c->repeat / 2] / n : 0.0, "us");
        run_log(run, "%d particles: %ld fcc, %ld hcp, %ld bcc, %ld ico, %ld other12, %ld not12, "
                     "%ld surface, %ld coord4, %ld not4 (cutoff %.4f Å, %s); %.3f us/particle",
                n, counts[STRUCT_FCC], counts[STRUCT_HCP], counts[STRUCT_BCC], counts[STRUCT_ICO],
                counts[STRUCT_OTHER12], counts[STRUCT_NOT12], counts[STRUCT_SURFACE],
                counts[STRUCT_COORD4], counts[STRUCT_NOT4], c->sp.cutoff,
                cna_mode_names[c->sp.mode], n > 0 ? 1e6 * times[c->repeat / 2] / n : 0.0);
        /* one snapshot with the classes */
        if (run->h5_open) {
            hid_t g = h5out_begin_snapshot(&run->h5, "particles", 0, 0.0, n, e);
            if (g < 0) {
                rc = ERR_RUNTIME;
            } else {
                int64_t *ib = malloc((size_t)(n + 1) * sizeof *ib);
                rc = run_snapshot_cell(run, g, &c->box, e);
                if (!rc)
                    rc = h5out_write_doubles(&run->h5, g, "position", p->x, n, 3, "Å", e);
                for (int i = 0; ib && i < n; i++)
                    ib[i] = p->id[i];
                if (!rc && ib)
                    rc = h5out_write_ints(&run->h5, g, "id", ib, n, "1", e);
                if (!rc)
                    rc = h5out_write_doubles(&run->h5, g, "structure", f, n, 1, "1", e);
                free(ib);
                h5out_end_snapshot(&run->h5, g);
            }
        }
    }
    frame_free(&fr);
    free(cls);
    free(times);
    free(cpu);
    run->steps_run = c->repeat;
    return rc;
}

static void structure_destroy(void *state)
{
    struct structure_case *c = state;
    if (!c)
        return;
    particles_destroy(&c->p);
    free(c);
}

static long structure_particles(const void *state)
{
    const struct structure_case *c = state;
    return c && c->p ? c->p->n_owned : 0;
}

const struct case_type structure_case_type = {
    "structure", "local crystalline order (CNA, coordination, surface) of a configuration",
    structure_read, structure_run, structure_destroy, structure_particles, NULL,
    .checkpoints = 0,
};
