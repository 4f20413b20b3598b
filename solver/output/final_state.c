/* final_state: output.final_state on one process or on bricks (final_state.h). */
#include "output/final_state.h"

#include <string.h>

#include "output/lammps_data_write.h"
#include "output/xyz_write.h"
#include "util/wfile.h"

/* Rank 0's writer during the walks over the windows. */
struct final_walk {
    FILE *f;
    const char *path;
    int xyz, velocities;
};

static int write_window(void *ctx, struct particles *q, struct err *e)
{
    const struct final_walk *w = ctx;
    if (w->xyz)
        xyz_write_particles(w->f, q, NULL);
    else if (w->velocities)
        lammps_data_velocities(w->f, q);
    else
        lammps_data_atoms(w->f, q);
    return ferror(w->f) ? err_set(e, ERR_RUNTIME, "cannot write %s: write error", w->path) : 0;
}

int final_state_write(struct run *run, struct halo *halo, const struct particles *p,
                      const struct box *b, long step, double time, struct err *e)
{
    /* the same options on every rank, so all ranks walk or none */
    const char *name = run->out.final_state;
    if (!name)
        return 0;
    if (!halo)
        return run_write_final_state(run, p, b, step, time, e);
    /* bricks: rank 0 writes the header with the totals of every rank, then
     * the particles in id order a window at a time (halo_gather_windows),
     * so no rank holds them all: the serial run's atoms and values, in id
     * order (a serial run writes its own order) */
    const char *dot = strrchr(name, '.');
    int root = run->opt.rank == 0;
    struct final_walk w = {NULL, NULL, dot && strcmp(dot, ".xyz") == 0, 0};
    double total = (double)p->n_owned;
    halo_sum(halo, &total, 1);
    double lo[3] = {b->lo[0], b->lo[1], b->lo[2]}, hi[3] = {b->hi[0], b->hi[1], b->hi[2]};
    lammps_data_widen(p, b, lo, hi);
    double ext[6] = {-lo[0], -lo[1], -lo[2], hi[0], hi[1], hi[2]};
    halo_max(halo, ext, 6);
    for (int d = 0; d < 3; d++) {
        lo[d] = -ext[d];
        hi[d] = ext[3 + d];
    }
    char path[4096];
    run_path(run, name, path, sizeof path);
    w.path = path;
    struct wfile file = {0};
    int rc = root ? wfile_open(&file, path, e) : 0;
    if (!rc && root) {
        w.f = file.f;
        if (w.xyz) {
            xyz_write_header(w.f, (long)total, b, step, time, 0, 0, NULL);
        } else {
            char title[512];
            run_final_state_title(run, step, time, title, sizeof title);
            lammps_data_header(w.f, title, (long)total, p, lo, hi, b);
        }
    }
    rc = halo_agree(halo, rc, e);
    if (!rc)
        rc = halo_gather_windows(halo, p, 0, write_window, &w, e);
    if (!rc && !w.xyz) {   /* the data file's velocities: a second walk */
        w.velocities = 1;
        if (root)
            lammps_data_velocities_heading(w.f);
        rc = halo_gather_windows(halo, p, 0, write_window, &w, e);
    }
    if (root && !rc)
        rc = wfile_commit(&file, e);
    else if (root && w.f)
        wfile_discard(&file);
    if (root && !rc)
        run_final_state_recorded(run);
    return halo_agree(halo, rc, e);
}
