/* provenance: build facts captured by the Makefile (provenance.h in build/). */
#include "output/provenance.h"

#include <gsl/gsl_version.h>
#include <hdf5.h>
#include <sqlite3.h>
#include <stdio.h>
#include <yaml.h>

#include "build_info.h"

const char *provenance_version(void) { return CASCADE_VERSION; }
const char *provenance_git_hash(void) { return CASCADE_GIT_HASH; }

json_t *provenance_json(void)
{
    char hdf5[32];
    unsigned maj, min, rel;
    H5get_libversion(&maj, &min, &rel);
    snprintf(hdf5, sizeof hdf5, "%u.%u.%u", maj, min, rel);
    return json_pack("{s:s, s:s, s:s, s:s, s:s, s:{s:s, s:s, s:s, s:s, s:s}}", "version",
                     CASCADE_VERSION, "git_hash", CASCADE_GIT_HASH, "compiler", CASCADE_COMPILER,
                     "cflags", CASCADE_CFLAGS, "build", CASCADE_BUILD_VARIANT, "libraries", "hdf5",
                     hdf5, "gsl", GSL_VERSION, "jansson", JANSSON_VERSION, "libyaml",
                     yaml_get_version_string(), "sqlite", sqlite3_libversion());
}
