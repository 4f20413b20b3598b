/* fuzz_lammps_data: LAMMPS data files (system.read_data), read with type
 * names from the Masses comments and with system.elements given; a
 * configuration that reads is wrapped into its periodic box once, as the
 * first neighbour-list build of a run does. */
#include "core/box.h"
#include "core/particles.h"
#include "input/config_read.h"
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

#include <stdlib.h>

static void read_once(const char *path, const char *const *elements, int nelements)
{
    struct err e = {0};
    struct particles *p = particles_create(64);
    if (!p)
        abort();
    struct box b = {{0, 0, 0}, {0, 0, 0}, {BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC}, {0, 0, 0}};
    int rc = config_read_lammps_data(path, elements, nelements, NULL, p, &b, &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        rc = box_remap(&b, p, 0.0, &e);
        fuzz_check_error(rc, e.msg);
    }
    particles_destroy(&p);
}

int fuzz_lammps_data_one(const uint8_t *data, size_t size)
{
    static const char *const cuni[] = {"Cu", "Ni"};
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "conf.data", data, size, path, sizeof path);
    read_once(path, NULL, 0);
    read_once(path, cuni, 2);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(lammps_data)
