/* th: test helpers (see th.h). */
#define _XOPEN_SOURCE 700   /* nftw */
#include "helpers/th.h"

#include <criterion/criterion.h>
#include <fcntl.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/elements.h"
#include "util/cfg.h"
#include "util/yamldoc.h"

struct potential *th_potential(const char *yaml)
{
    json_t *doc;
    struct locmap *locs;
    struct err e = {0};
    int rc = yamldoc_load_string(yaml, strlen(yaml), "<test>", &doc, &locs, &e);
    cr_assert_eq(rc, 0, "yaml: %s", e.msg);
    struct cfg c = {"<test>", locs, &e, ".", 0};
    struct cfg_obj root;
    struct potential *pot = NULL;
    rc = cfg_root(&c, doc, &root);
    if (!rc)
        rc = potential_create(&root, &pot);
    cr_assert_eq(rc, 0, "potential: %s", e.msg);
    json_decref(doc);
    locmap_destroy(&locs);
    return pot;
}

struct particles *th_crystal(enum lattice_style style, double a, long n, const char *element,
                             double displace, unsigned seed, struct box *box)
{
    struct lattice l = {style, a, {0, 0, 0}, {{0}}};
    struct particles *p = particles_create(64);
    int t = particles_type_index(p, element, element_mass(element));
    int64_t id = 1;
    long cells[3] = {n, n, n};
    struct err e = {0};
    cr_assert(lattice_fill(&l, cells, NULL, p, t, &id, &e) > 0, "%s", e.msg);
    double cell[3];
    lattice_cell(&l, cell);
    for (int d = 0; d < 3; d++) {
        box->lo[d] = 0;
        box->hi[d] = n * cell[d];
        box->bc[d] = BOUNDARY_PERIODIC;
    }
    /* xorshift: a fixed, platform-independent sequence */
    unsigned s = seed ? seed : 1;
    for (int i = 0; i < p->n_owned; i++)
        for (int d = 0; d < 3; d++) {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            p->x[3 * i + d] += displace * (2.0 * (s / 4294967296.0) - 1.0);
        }
    return p;
}

void th_md(struct md *md, struct particles *p, const struct box *box, struct potential *pot,
           int nthreads)
{
    struct err e = {0};
    int rc = md_init(md, p, box, pot, 0.001, 0.5, nthreads, &e);
    cr_assert_eq(rc, 0, "md_init: %s", e.msg);
}

double th_energy(struct md *md)
{
    struct err e = {0};
    int rc = md_compute_forces(md, &e);
    cr_assert_eq(rc, 0, "forces: %s", e.msg);
    return md->last.energy;
}

int th_run(const char *const *argv, char *out, size_t outlen)
{
    int pipefd[2];
    cr_assert_eq(pipe(pipefd), 0);
    pid_t pid = fork();
    cr_assert(pid >= 0);
    if (pid == 0) {
        dup2(pipefd[1], 1);
        dup2(pipefd[1], 2);
        close(pipefd[0]);
        close(pipefd[1]);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    close(pipefd[1]);
    size_t len = 0;
    char buf[4096];
    ssize_t got;
    while ((got = read(pipefd[0], buf, sizeof buf)) > 0) {
        if (out && len + 1 < outlen) {
            size_t take = (size_t)got < outlen - 1 - len ? (size_t)got : outlen - 1 - len;
            memcpy(out + len, buf, take);
            len += take;
        }
    }
    close(pipefd[0]);
    if (out)
        out[len] = '\0';
    int status;
    waitpid(pid, &status, 0);
    if (WIFSIGNALED(status))
        return 128 + WTERMSIG(status);
    return WEXITSTATUS(status);
}

const char *th_solver(void)
{
    const char *s = getenv("CASCADE_SOLVER");
    return s ? s : "bin/cascade-solver";
}

const char *th_root(void)
{
    const char *s = getenv("CASCADE_ROOT");
    return s ? s : ".";
}

static char temp_dir[256];

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

/* The test process's scratch directory goes when the process ends, unless
 * CASCADE_KEEP_TEMP is set (to look at what a failing test wrote). */
static void remove_temp_dir(void)
{
    if (temp_dir[0] && !getenv("CASCADE_KEEP_TEMP"))
        nftw(temp_dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

const char *th_temp_dir(void)
{
    if (!temp_dir[0]) {
        snprintf(temp_dir, sizeof temp_dir, "/tmp/cascade-test-XXXXXX");
        cr_assert_not_null(mkdtemp(temp_dir));
        atexit(remove_temp_dir);
    }
    return temp_dir;
}

const char *th_write_temp(int slot, const char *name, const char *text)
{
    static char paths[8][512];
    cr_assert(slot >= 0 && slot < 8, "th_write_temp: slot %d of 8", slot);
    snprintf(paths[slot], sizeof paths[slot], "%s/%s", th_temp_dir(), name);
    FILE *f = fopen(paths[slot], "w");
    cr_assert_not_null(f);
    fputs(text, f);
    fclose(f);
    return paths[slot];
}
