/* fuzz_extxyz: extended XYZ files (system.read_xyz); a configuration that
 * reads is wrapped into its box once (periodic along the pbc axes, else
 * free), as the first neighbour-list build of a run does. */
#include "core/box.h"
#include "core/particles.h"
#include "input/config_read.h"
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

#include <stdlib.h>

int fuzz_extxyz_one(const uint8_t *data, size_t size)
{
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "conf.xyz", data, size, path, sizeof path);
    struct err e = {0};
    struct particles *p = particles_create(64);
    if (!p)
        abort();
    struct box b = {{0, 0, 0}, {0, 0, 0}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    int pbc[3];
    int rc = config_read_extxyz(path, NULL, p, &b, pbc, &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        for (int d = 0; d < 3; d++)
            b.bc[d] = pbc[d] ? BOUNDARY_PERIODIC : BOUNDARY_FREE;
        rc = box_remap(&b, p, 0.0, &e);
        fuzz_check_error(rc, e.msg);
    }
    particles_destroy(&p);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(extxyz)
