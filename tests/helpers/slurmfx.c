/* slurmfx: a private one-node Slurm cluster for a test (see slurmfx.h). */
#include "slurmfx.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *const daemon_names[3] = {"munged", "slurmctld", "slurmd"};

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void nap(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&ts, NULL);
}

static int port_free(int port)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0)
        return 0;
    int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((unsigned short)port);
    a.sin_addr.s_addr = htonl(INADDR_ANY);
    int ok = bind(fd, (struct sockaddr *)&a, sizeof a) == 0;
    close(fd);
    return ok;
}

static void tail_of(const char *path, char *out, size_t len)
{
    out[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f)
        return;
    char buf[8192];
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, size > 1500 ? size - 1500 : 0, SEEK_SET);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    snprintf(out, len, "%s", buf);
}

static pid_t start_daemon(struct slurmfx *f, const char *const *argv, const char *log)
{
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid != 0)
        return pid;
    /* dies with the test process, however that ends */
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent)
        _exit(127);
    setpgid(0, 0);
    int fd = open(log, O_WRONLY | O_CREAT | O_APPEND, 0644);
    int null = open("/dev/null", O_RDONLY);
    if (fd < 0 || null < 0 || dup2(null, 0) < 0 || dup2(fd, 1) < 0 || dup2(fd, 2) < 0)
        _exit(127);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    if (chdir(f->dir) != 0)
        _exit(127);
    execvp(argv[0], (char *const *)argv);
    dprintf(2, "cannot run %s: %s\n", argv[0], strerror(errno));
    _exit(127);
}

int slurmfx_client(const char *const *argv, char *out, size_t len)
{
    int p[2];
    if (pipe(p) != 0)
        return -1;
    pid_t pid = fork();
    if (pid == 0) {
        dup2(p[1], 1);
        int null = open("/dev/null", O_WRONLY);
        dup2(null, 2);
        close(p[0]);
        close(p[1]);
        execvp(argv[0], (char *const *)argv);
        _exit(127);
    }
    close(p[1]);
    size_t n = 0;
    char buf[4096];
    ssize_t got;
    while ((got = read(p[0], buf, sizeof buf)) > 0)
        if (out && n + 1 < len) {
            size_t take = (size_t)got < len - 1 - n ? (size_t)got : len - 1 - n;
            memcpy(out + n, buf, take);
            n += take;
        }
    close(p[0]);
    if (out)
        out[n] = '\0';
    int st;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

/* Whether a started daemon already exited; fills skip with its log. */
static int died(struct slurmfx *f, int k, const char *cmd, const char *log)
{
    int st;
    if (waitpid(f->pid[k], &st, WNOHANG) != f->pid[k])
        return 0;
    f->pid[k] = 0;
    char t[800], o[800], out[256];
    tail_of(log, t, sizeof t);
    snprintf(out, sizeof out, "%s/log/%s.out", f->dir, daemon_names[k]);
    tail_of(out, o, sizeof o);
    snprintf(f->skip, sizeof f->skip, "'%s' exited (%s %d): %s%s%s", cmd,
             WIFEXITED(st) ? "exit" : "signal", WIFEXITED(st) ? WEXITSTATUS(st) : WTERMSIG(st),
             o, o[0] && t[0] ? " / " : "", t);
    return 1;
}

int slurmfx_start(struct slurmfx *f, const struct slurmfx_opts *o)
{
    memset(f, 0, sizeof *f);
    snprintf(f->partition, sizeof f->partition, "test");
    snprintf(f->dir, sizeof f->dir, "/tmp/cascade-slurm-XXXXXX");
    if (!mkdtemp(f->dir)) {
        snprintf(f->skip, sizeof f->skip, "mkdtemp: %s", strerror(errno));
        return -1;
    }
    /* munged wants every directory up to its socket searchable by all */
    chmod(f->dir, 0755);
    char path[512], host[256] = "";
    const char *dirs[] = {"state", "spool", "log", "munge"};
    for (int i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/%s", f->dir, dirs[i]);
        mkdir(path, 0755);
    }
    gethostname(host, sizeof host);
    host[strcspn(host, ".")] = '\0';
    /* a key of our own (munged refuses one others can read) */
    char key[512];
    snprintf(key, sizeof key, "%s/munge/munge.key", f->dir);
    int kfd = open(key, O_WRONLY | O_CREAT | O_TRUNC, 0400);
    unsigned char kb[1024];
    FILE *ur = fopen("/dev/urandom", "rb");
    int keyok = kfd >= 0 && ur && fread(kb, 1, sizeof kb, ur) == sizeof kb &&
                write(kfd, kb, sizeof kb) == (ssize_t)sizeof kb;
    if (ur)
        fclose(ur);
    if (kfd >= 0)
        close(kfd);
    if (!keyok) {
        snprintf(f->skip, sizeof f->skip, "cannot write a munge key to %s", key);
        return -1;
    }
    /* ports nobody else uses: from the pid, moved on while taken */
    int port = 20000 + (int)(getpid() % 2000) * 8;
    for (int tries = 0; tries < 200 && !(port_free(port) && port_free(port + 1)); tries++)
        port = 20000 + (port - 20000 + 8) % 16000;
    snprintf(f->conf, sizeof f->conf, "%s/slurm.conf", f->dir);
    FILE *c = fopen(f->conf, "w");
    if (!c) {
        snprintf(f->skip, sizeof f->skip, "cannot write %s", f->conf);
        return -1;
    }
    fprintf(c,
            "ClusterName=cascadetest\n"
            "SlurmctldHost=%s\n"
            "SlurmUser=root\nSlurmdUser=root\n"
            "AuthType=auth/munge\nCredType=cred/munge\n"
            "AuthInfo=socket=%s/munge/sock\n"
            "SlurmctldPort=%d\nSlurmdPort=%d\n"
            "StateSaveLocation=%s/state\nSlurmdSpoolDir=%s/spool\n"
            "SlurmctldPidFile=%s/slurmctld.pid\nSlurmdPidFile=%s/slurmd.pid\n"
            "SlurmctldLogFile=%s/log/slurmctld.log\nSlurmdLogFile=%s/log/slurmd.log\n"
            "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
            "SelectType=select/cons_tres\nSelectTypeParameters=CR_Core_Memory\n"
            "SchedulerType=sched/backfill\nMpiDefault=none\nReturnToService=2\n"
            "SlurmdParameters=config_overrides\nDefMemPerCPU=100\n"
            "KillWait=2\nMinJobAge=60\nSchedulerParameters=sched_interval=2\n"
            "JobAcctGatherType=jobacct_gather/none\n",
            host, f->dir, port, port + 1, f->dir, f->dir, f->dir, f->dir, f->dir, f->dir);
    if (o && o->max_array_size > 0)
        fprintf(c, "MaxArraySize=%d\n", o->max_array_size);
    fprintf(c, "NodeName=%s CPUs=%d RealMemory=8000 State=UNKNOWN\n", host,
            o && o->cpus ? o->cpus : 8);
    fprintf(c, "PartitionName=%s Nodes=ALL Default=YES MaxTime=%s State=UP\n", f->partition,
            o && o->max_time ? o->max_time : "10:00");
    fclose(c);
    setenv("SLURM_CONF", f->conf, 1);

    char sock[256], log[3][256], pidf[256], seed[256], kf[300];
    snprintf(sock, sizeof sock, "--socket=%s/munge/sock", f->dir);
    snprintf(kf, sizeof kf, "--key-file=%s", key);
    snprintf(pidf, sizeof pidf, "--pid-file=%s/munge/munged.pid", f->dir);
    snprintf(seed, sizeof seed, "--seed-file=%s/munge/seed", f->dir);
    char mlog[300];
    snprintf(mlog, sizeof mlog, "--log-file=%s/log/munged.log", f->dir);
    for (int k = 0; k < 3; k++)
        snprintf(log[k], sizeof log[k], "%s/log/%s.out", f->dir, daemon_names[k]);
    const char *munged[] = {"munged", "-F", sock, kf, pidf, seed, mlog, NULL};
    f->pid[0] = start_daemon(f, munged, log[0]);
    snprintf(path, sizeof path, "%s/munge/sock", f->dir);
    struct stat sb;
    double t0 = now_s();
    while (stat(path, &sb) != 0) {
        char ml[300];
        snprintf(ml, sizeof ml, "%s/log/munged.log", f->dir);
        if (died(f, 0, "munged -F --socket=DIR/munge/sock --key-file=DIR/munge/munge.key", ml))
            return -1;
        if (now_s() - t0 > 10) {
            snprintf(f->skip, sizeof f->skip, "munged made no socket %s in 10 s", path);
            return -1;
        }
        nap(0.05);
    }
    const char *ctld[] = {"slurmctld", "-D", "-i", "-f", f->conf, NULL};
    const char *slurmd[] = {"slurmd", "-D", "-f", f->conf, NULL};
    f->pid[1] = start_daemon(f, ctld, log[1]);
    f->pid[2] = start_daemon(f, slurmd, log[2]);
    /* the node is idle once slurmd registered with the controller */
    t0 = now_s();
    for (;;) {
        char out[256] = "";
        const char *sinfo[] = {"sinfo", "-h", "-N", "-o", "%t", NULL};
        if (slurmfx_client(sinfo, out, sizeof out) == 0 && strncmp(out, "idle", 4) == 0)
            return 0;
        char lp[300];
        snprintf(lp, sizeof lp, "%s/log/slurmctld.log", f->dir);
        if (died(f, 1, "slurmctld -D -i -f DIR/slurm.conf", lp))
            return -1;
        snprintf(lp, sizeof lp, "%s/log/slurmd.log", f->dir);
        if (died(f, 2, "slurmd -D -f DIR/slurm.conf", lp))
            return -1;
        if (now_s() - t0 > 30) {
            char t[1200];
            tail_of(lp, t, sizeof t);
            snprintf(f->skip, sizeof f->skip,
                     "sinfo did not show the node idle within 30 s (last: '%s'); slurmd.log: %s",
                     out, t);
            return -1;
        }
        nap(0.1);
    }
}

void slurmfx_stop(struct slurmfx *f)
{
    if (f->pid[1] > 0) {
        /* what the test left in the queue goes first, so no job outlives it */
        const char *sc[] = {"scancel", "--user=root", NULL};
        slurmfx_client(sc, NULL, 0);
        for (double t0 = now_s(); now_s() - t0 < 5;) {
            char out[4096] = "";
            const char *sq[] = {"squeue", "-h", "-o", "%i", NULL};
            if (slurmfx_client(sq, out, sizeof out) != 0 || !out[0])
                break;
            nap(0.2);
        }
    }
    for (int k = 2; k >= 0; k--) {
        if (f->pid[k] <= 0)
            continue;
        kill(f->pid[k], SIGTERM);
        int st, gone = 0;
        for (double t0 = now_s(); now_s() - t0 < 10 && !gone;) {
            gone = waitpid(f->pid[k], &st, WNOHANG) == f->pid[k];
            if (!gone)
                nap(0.05);
        }
        if (!gone) {
            kill(f->pid[k], SIGKILL);
            waitpid(f->pid[k], &st, 0);
        }
        f->pid[k] = 0;
    }
    if (f->dir[0] && !getenv("CASCADE_KEEP_SLURM")) {
        const char *rm[] = {"rm", "-rf", f->dir, NULL};
        slurmfx_client(rm, NULL, 0);
    }
    unsetenv("SLURM_CONF");
}
