/* study_run: plan, register and run a study (see study_run.h). */
#include "study_run.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "backend_mpi.h"
#include "backend_slurm.h"
#include "db.h"
#include "launch.h"
#include "plan.h"
#include "sysinfo.h"

int study_run(const struct study *s, const struct study_run_opts *o, struct runner_summary *sum,
              struct err *e)
{
    struct solver sv;
    struct plan p;
    memset(sum, 0, sizeof *sum);
    int rc = solver_open(&sv, o->solver, e);
    if (!rc)
        rc = plan_build(&p, s, &sv, e);
    if (rc)
        return rc;
    if (o->plan_filter && (rc = o->plan_filter(o->filter_ctx, &p, e))) {
        plan_free(&p);
        return rc;
    }
    struct backend b;
    memset(&b, 0, sizeof b);
    /* Slurm: the resources of every job are checked against the cluster
     * before anything is written */
    if (s->backend == STUDY_BACKEND_SLURM && o->mpi_size <= 1) {
        rc = backend_slurm_create(&b, s, &p, o->runs, e);
        if (rc) {
            plan_free(&p);
            return rc;
        }
    }
    /* every check has passed: from here on the database and runs/ are written */
    char runs_abs[4096];
    sqlite3 *db = NULL;
    rc = launch_mkdirs(o->runs, e);
    if (!rc && !realpath(o->runs, runs_abs))
        rc = err_set(e, ERR_RUNTIME, "%s: %s", o->runs, strerror(errno));
    if (!rc)
        rc = db_open(o->db_path, &db, e);
    if (!rc && !b.impl) {
        if (o->mpi_size > 1) {
            rc = backend_mpi_create(&b, o->mpi_size - 1, e);
        } else {
            long slots = o->jobs;
            if (!slots) {
                long per_job = s->threads * (s->mpirun_np ? s->mpirun_np : 1);
                slots = sys_ncpu() / per_job;
                if (slots < 1)
                    slots = 1;
            }
            rc = backend_local_create(&b, (int)slots, e);
        }
    }
    if (!rc) {
        struct runner_options ro = {.runs_root = runs_abs,
                                    .lease_s = o->lease,
                                    .poll_s = 1.0,
                                    .quiet = o->quiet,
                                    .log = stderr,
                                    .infra_backoff_s = o->infra_pause > 0 ? o->infra_pause : 0.5,
                                    .infra_limit = 3};
        rc = runner_run(s, &p, &sv, db, &b, &ro, sum, e);
        if (s->backend == STUDY_BACKEND_SLURM && b.impl && !o->quiet)
            backend_slurm_report(&b, stderr);
    }
    if (b.destroy)
        b.destroy(&b);
    db_close(&db);
    plan_free(&p);
    return rc;
}
