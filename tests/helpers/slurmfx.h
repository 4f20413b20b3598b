/*
 * slurmfx: a one-node Slurm cluster of the test's own -- munged with its own
 * key and socket, slurmctld and slurmd in the foreground, all under a fresh
 * temporary directory with ports of their own (so tests running side by
 * side never share a cluster), SLURM_CONF set in the test process (so every
 * cascade and Slurm client it starts talks to this cluster).  The node
 * claims `cpus` CPUs (SlurmdParameters=config_overrides), so throttles can
 * be tested on a small machine.  slurmfx_stop cancels what is left and stops
 * exactly the three processes slurmfx_start started; they also die with the
 * test process (PR_SET_PDEATHSIG), whatever ends it.
 */
#ifndef CASCADE_TEST_SLURMFX_H
#define CASCADE_TEST_SLURMFX_H

#include <sys/types.h>

struct slurmfx_opts {
    int cpus;                /* 0: 8 */
    int max_array_size;      /* 0: Slurm's default */
    const char *max_time;    /* the partition's MaxTime, NULL: "10:00" */
};

struct slurmfx {
    char dir[128];
    char conf[192];
    char partition[32];
    pid_t pid[3];            /* munged, slurmctld, slurmd */
    char skip[2048];         /* why the cluster could not start, or "" */
};

/* 0 when the node is idle; -1 with f->skip saying why (command and message). */
int slurmfx_start(struct slurmfx *f, const struct slurmfx_opts *o);
void slurmfx_stop(struct slurmfx *f);

/* Run a Slurm client (argv[0] on PATH) against the cluster; stdout into out. */
int slurmfx_client(const char *const *argv, char *out, size_t len);

#endif
