/*
 * md_kernel_probe: the cost of one MD force call and of one neighbour-list
 * build, apart from everything else a run does, for the kernel work of
 * issue 18.  It builds a periodic crystal (fcc Cu for EAM, diamond Si for
 * Stillinger-Weber), displaces every atom by up to 0.1 Å (about the
 * thermal displacement at 600 K), calls the potential REPEAT times and
 * prints the fastest and the median call in CPU time: on a shared machine
 * the fastest of many calls is the figure least moved by the other
 * processes, and CPU time does not count the time the process waited.
 *
 *   md_kernel_probe eam|sw CELLS [REPEAT]
 *   -> "pairs P force_min_ms M force_median_ms D list_min_ms L ns_per_pair N"
 *
 * pairs: pairs closer than the cutoff (each once); ns_per_pair: the fastest
 * force call over those pairs.  Built by bench/bench_md_kernel.sh against
 * the release build's libraries.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <jansson.h>

#include "core/lattice.h"
#include "core/particles.h"
#include "md/md.h"
#include "md/potential.h"
#include "util/cfg.h"
#include "util/yamldoc.h"

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static struct potential *make_potential(const char *yaml, struct err *e)
{
    json_t *doc = NULL;
    struct locmap *locs = NULL;
    struct potential *pot = NULL;
    if (yamldoc_load_string(yaml, strlen(yaml), "<probe>", &doc, &locs, e))
        return NULL;
    struct cfg c = {"<probe>", locs, e, ".", 0};
    struct cfg_obj root;
    if (!cfg_root(&c, doc, &root))
        potential_create(&root, &pot);
    json_decref(doc);
    locmap_destroy(&locs);
    return pot;
}

int main(int argc, char **argv)
{
    if (argc < 3 || (strcmp(argv[1], "eam") != 0 && strcmp(argv[1], "sw") != 0)) {
        fprintf(stderr, "usage: md_kernel_probe eam|sw CELLS [REPEAT]\n");
        return 2;
    }
    int is_eam = strcmp(argv[1], "eam") == 0;
    long n = atol(argv[2]);
    int repeat = argc > 3 ? atoi(argv[3]) : 20;
    if (n < 3 || n > 200 || repeat < 1 || repeat > 100000) {
        fprintf(stderr, "md_kernel_probe: CELLS in 3..200, REPEAT in 1..100000\n");
        return 2;
    }
    struct err e = {0};
    struct lattice l = {is_eam ? LATTICE_FCC : LATTICE_DIAMOND, is_eam ? 3.615 : 5.431,
                        {0, 0, 0}, {{0}}};
    const char *element = is_eam ? "Cu" : "Si";
    struct particles *p = particles_create(64);
    int t = particles_type_index(p, element, element_mass(element));
    int64_t id = 1;
    long cells[3] = {n, n, n};
    if (lattice_fill(&l, cells, NULL, p, t, &id, &e) <= 0) {
        fprintf(stderr, "md_kernel_probe: %s\n", e.msg);
        return 1;
    }
    struct box box = {0};
    double cell[3];
    lattice_cell(&l, cell);
    for (int d = 0; d < 3; d++) {
        box.lo[d] = 0;
        box.hi[d] = n * cell[d];
        box.bc[d] = BOUNDARY_PERIODIC;
    }
    unsigned s = 12345;   /* xorshift: the same displacements everywhere */
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++) {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            p->x[3 * i + d] += 0.1 * (2.0 * (s / 4294967296.0) - 1.0);
        }
    struct potential *pot = make_potential(
        is_eam ? "style: eam/alloy\nfile: Cu_mishin1.eam.alloy\n"
               : "style: sw\nfile: Si.sw\nelements: [Si]\n", &e);
    if (!pot) {
        fprintf(stderr, "md_kernel_probe: potential: %s\n", e.msg);
        return 1;
    }
    struct md md;
    /* skin 1 Å as bench/cases/md_eam_32k.yaml (EAM) and LAMMPS' metal default (SW) */
    if (md_init(&md, p, &box, pot, 0.001, 1.0, 1, &e)) {
        fprintf(stderr, "md_kernel_probe: %s\n", e.msg);
        return 1;
    }
    /* pairs within the cutoff, each once */
    const struct nlist *nl = md.nl;
    double rc2 = md.pot->cutoff * md.pot->cutoff;
    long pairs = 0;
    for (int i = 0; i < md.p->n_owned; i++)
        for (int k = nl->offset[i]; k < nl->offset[i + 1]; k++) {
            const double *xi = md.p->x + 3 * i, *xj = md.p->x + 3 * nl->neigh[k];
            double r2 = 0;
            for (int d = 0; d < 3; d++)
                r2 += (xi[d] - xj[d]) * (xi[d] - xj[d]);
            pairs += r2 < rc2;
        }
    if (nl->kind == NLIST_FULL)
        pairs /= 2;
    double *tf = malloc((size_t)repeat * sizeof *tf);
    if (!tf)
        return 1;
    for (int r = 0; r < repeat; r++) {
        struct force_result fr;
        double t0 = cpu_seconds();
        if (md.pot->ops->compute(md.pot, md.p, md.nl, 0, &fr, &e)) {
            fprintf(stderr, "md_kernel_probe: %s\n", e.msg);
            return 1;
        }
        tf[r] = cpu_seconds() - t0;
    }
    int nlb = repeat < 10 ? repeat : 10;
    double tl = 1e30;
    for (int r = 0; r < nlb; r++) {
        double t0 = cpu_seconds();
        if (nlist_build(md.nl, md.p, &e)) {
            fprintf(stderr, "md_kernel_probe: %s\n", e.msg);
            return 1;
        }
        double dt = cpu_seconds() - t0;
        tl = dt < tl ? dt : tl;
    }
    qsort(tf, (size_t)repeat, sizeof *tf, cmp_double);
    printf("atoms %d pairs %ld force_min_ms %.4f force_median_ms %.4f list_min_ms %.4f "
           "ns_per_pair %.3f\n", md.p->n_owned, pairs, 1e3 * tf[0], 1e3 * tf[repeat / 2],
           1e3 * tl, 1e9 * tf[0] / (double)pairs);
    free(tf);
    md_free(&md);
    return 0;
}
