/*
 * sim: one simulation, and the one time loop every time-stepping case type
 * runs on.  Start here.
 *
 * A simulation is
 *   - its models: each physics engine that advances state (MD, DPD, MPM, a
 *     coupling), a table of stage functions (struct sim_model_ops) and the
 *     model's own state;
 *   - the schedule: steps in declared phases (a piston phase, a release
 *     phase, ...), and the cadence of thermo rows, snapshots, XYZ frames and
 *     checkpoints (the case's `output` section);
 *   - the case type's hooks (struct sim_case_ops): its outputs, its
 *     accumulators, its metrics -- what makes an impact an impact;
 *   - the run: output files, result.json, timers, progress (output/run.h).
 *
 * sim_run() owns the loop.  Each step calls, in this order,
 *     every model's pre_force   (first half kick, drift, boundary motion)
 *     every model's force       (ghosts, lists, forces; couplings last)
 *     every model's integrate   (second half kick, thermostat, grid update)
 *     every model's post_step   (couplings acting on the advanced state)
 * then, once for the whole simulation:
 *     the divergence check      (each model's observe: finite energy, and
 *                                the energy change of conserving models)
 *     the case's after_step     (accumulators, a phase's stop condition)
 *     outputs that are due      (the case's output hook)
 *     a checkpoint when due     (every model's and the case's state)
 *     progress with ETA, per-phase timers.
 * A restarted run (sim_run with a checkpoint path) reads every model's and
 * the case's state back and continues from the stored step: the same final
 * state as the uninterrupted run, bitwise, on the same thread count.
 */
#ifndef CASCADE_SIM_H
#define CASCADE_SIM_H

#include "output/checkpoint.h"
#include "output/run.h"
#include "util/err.h"

#define SIM_MAX_MODELS 4
#define SIM_MAX_PHASES 8

struct sim;

/* A model's energy after a step, for the divergence check. */
struct sim_energy {
    double total;            /* must stay finite */
    int conserved;           /* 1: total must stay near its value at step 0 */
    double scale;            /* the change is reported as (total - initial) / scale */
    double limit;            /* > 0: diverged when |change| exceeds it */
    const char *limit_key;   /* the case key that sets the limit, for the message */
    const char *unit;        /* unit of the change ("eV/atom", ...) */
};

/* A physics engine as stages.  NULL stages are skipped. */
struct sim_model_ops {
    const char *name;        /* also the checkpoint group /model/<name> (sim_add_model) */
    /* forces and energies at step 0; on a restart it runs too, before the
     * checkpoint is read, which then replaces the state */
    int (*init)(void *self, struct sim *s, struct err *e);
    int (*pre_force)(void *self, struct sim *s, struct err *e);
    int (*force)(void *self, struct sim *s, struct err *e);
    int (*integrate)(void *self, struct sim *s, struct err *e);
    /* after every model integrated: couplings and boundaries that act on
     * the advanced state */
    int (*post_step)(void *self, struct sim *s, struct err *e);
    void (*observe)(void *self, const struct sim *s, struct sim_energy *en);
    /* the complete state the next step needs; checkpoint_read runs after
     * the case has been built from its case file, and replaces state */
    int (*checkpoint_write)(void *self, struct ckpt *ck, struct err *e);
    int (*checkpoint_read)(void *self, struct ckpt *ck, struct err *e);
    /* before checkpoint_write, on every MPI rank (checkpoint_write runs on
     * rank 0 only): a decomposed model gathers its state there, or counts
     * what each rank will write with checkpoint_write_part */
    int (*checkpoint_collect)(void *self, struct err *e);
    /* under MPI, after rank 0 wrote and closed the checkpoint, on every
     * rank with the file open through MPI-IO (ckpt_open_parallel) and the
     * model's group entered: a decomposed model writes its own particles
     * into the datasets checkpoint_write laid out (ckpt_put_particles_part).
     * Collective.  NULL: nothing distributed.  A checkpoint is read on
     * every rank through MPI-IO as well (checkpoint_read on every rank). */
    int (*checkpoint_write_part)(void *self, struct ckpt *ck, struct err *e);
    /* a checkpoint was just written (or read): the model puts itself in
     * the state both runs continue from (e.g. a fresh neighbour list) */
    void (*checkpoint_sync)(void *self);
};

struct sim_model {
    const struct sim_model_ops *ops;
    void *self;              /* owned by the case type */
    const char *name;        /* checkpoint group /model/<name>: ops->name, or the
                              * instance's own name when one model runs more than
                              * once (a reference run beside the run) */
};

/* A named stretch of the schedule. */
struct sim_phase {
    const char *name;
    long steps;
};

/* What a case type adds to the loop.  Every hook may be NULL. */
struct sim_case_ops {
    /* outputs opened (after a restore, the restored state is in place) */
    int (*begin)(void *c, struct sim *s, struct err *e);
    /* phase `phase` starts with the next step */
    int (*phase_begin)(void *c, struct sim *s, int phase, struct err *e);
    /* after every step's divergence check: accumulate; may set s->stop */
    int (*after_step)(void *c, struct sim *s, struct err *e);
    /* outputs due at s->step: SIM_DUE_* bits */
    int (*output)(void *c, struct sim *s, unsigned due, struct err *e);
    /* metrics into s->run->result (also after a divergence: rc says so);
     * outputs closed */
    int (*report)(void *c, struct sim *s, int rc, struct err *e);
    int (*checkpoint_write)(void *c, struct ckpt *ck, struct err *e);
    int (*checkpoint_read)(void *c, struct ckpt *ck, struct err *e);
};

enum sim_due {
    SIM_DUE_THERMO = 1,
    SIM_DUE_SNAPSHOT = 2,
    SIM_DUE_XYZ = 4,
    SIM_DUE_LAST = 8,        /* the last step of the run */
};

struct sim {
    struct run *run;                 /* borrowed: outputs, result, timers, log */
    struct sim_model model[SIM_MAX_MODELS];
    int nmodels;
    const struct sim_case_ops *case_ops;
    void *case_state;

    /* schedule */
    struct sim_phase phase[SIM_MAX_PHASES];
    int nphases;
    long steps;                      /* total over the phases */
    double dt;                       /* ps per step (models with their own
                                      * adaptive step set it in pre_force) */
    long checkpoint_every;           /* 0: no checkpoints */

    /* state of the loop */
    long step;                       /* steps done */
    double time;                     /* ps */
    int cur_phase;
    long phase_step;                 /* steps done in the current phase */
    int stop;                        /* set by the case: end after this step */
    long restarted_from;             /* step of the checkpoint continued from, or -1 */
    int subrun;                      /* a stretch of dynamics inside a case (a
                                      * thermal average, one shock of several):
                                      * no progress, checkpoints or kill hook;
                                      * run may be NULL (no outputs) */
    struct timers own_timers;        /* when run is NULL */
    struct sim_energy e0[SIM_MAX_MODELS];   /* energies at step 0 */
    int peratom;                     /* per-particle energies needed this step */
    char diverged[256];              /* why the run diverged ("" if not) */
};

/* An empty simulation on run r: one phase of `steps` steps of `dt` ps, the
 * output cadence from r->out.  sim_init_subrun: a stretch of dynamics
 * inside a case, on run r (may be NULL): the loop, the divergence check
 * and the timers, without progress, checkpoints or snapshots of its own. */
void sim_init(struct sim *s, struct run *r, long steps, double dt);
void sim_init_subrun(struct sim *s, struct run *r, long steps, double dt);
int sim_add_model(struct sim *s, const struct sim_model_ops *ops, void *self, struct err *e);
/* The same with an instance name (a static string) for the model's
 * checkpoint group: the instances of one model need distinct names. */
int sim_add_model_named(struct sim *s, const struct sim_model_ops *ops, void *self,
                        const char *name, struct err *e);
/* Replace the single phase by declared phases (their steps add up). */
int sim_add_phase(struct sim *s, const char *name, long steps, struct err *e);

/* Run to the end (or the case's stop).  `restart`: a checkpoint file to
 * continue from (NULL: from step 0).  Returns ERR_DIVERGED with the reason
 * in e when the run diverged. */
int sim_run(struct sim *s, const char *restart, struct err *e);

/* Whether an output with interval `every` is due at step s of this run. */
int sim_due(const struct sim *s, long every);

/* The newest valid checkpoint in dir (or the file itself when `path` is a
 * file) into out; ERR_INPUT naming the path when there is none. */
int sim_find_checkpoint(const char *path, const char *case_key, char *out, size_t len,
                        struct err *e);

#endif
