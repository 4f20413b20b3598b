/*
 * potential: the interface every interatomic potential implements, and the
 * registry that selects one by name from the case file (LAMMPS's style
 * registry).  Adding a potential means one file and one line in
 * potential_registry.c.
 *
 * compute() fills, for owned and ghost particles, the force f, and when
 * asked the per-particle energy pe and virial; the caller adds ghost
 * contributions back to the owners.  It returns the total energy and the
 * virial tensor W_ab = sum over pairs of r_ab f_ab (eV).
 */
#ifndef CASCADE_POTENTIAL_H
#define CASCADE_POTENTIAL_H

#include "core/elements.h"
#include "core/particles.h"
#include "core/neighbor.h"
#include "util/cfg.h"
#include "util/err.h"

enum { POT_PERATOM = 1 };   /* compute flags: per-particle energy and virial */

struct force_result {
    double energy;       /* eV */
    double virial[6];    /* eV: xx yy zz xy xz yz */
};

struct potential;

struct potential_ops {
    const char *style;
    int (*compute)(struct potential *pot, struct particles *p, const struct nlist *nl, int flags,
                   struct force_result *out, struct err *e);
    void (*destroy)(struct potential *pot);
};

/* Base struct: the first member of every concrete potential. */
struct potential {
    const struct potential_ops *ops;
    double cutoff;                 /* Å */
    enum nlist_kind list_kind;     /* half or full neighbour list */
    int nelements;
    char element[PARTICLES_MAX_TYPES][16];
    double mass[PARTICLES_MAX_TYPES];   /* amu, from the file where it has one */
    int nthreads;                  /* OpenMP threads for the force loops */
    int type_map[PARTICLES_MAX_TYPES];  /* particle type -> element index (potential_bind) */
    char description[256];         /* one line for logs and provenance */
    char source_path[512];         /* the potential file used, if any */
    char cutoff_source[600];       /* "file:line" the cutoff comes from ("": case keys) */
};

/* Read the `potential` section (style + the style's keys) and create the
 * potential (*out stays NULL in shallow mode).  Files are found by path, or by name in the directory of
 * CASCADE_POTENTIALS, then /usr/share/lammps/potentials. */
int potential_create(struct cfg_obj *o, struct potential **out);
void potential_destroy(struct potential **pot);

/* Map particle types to the potential's elements (fills pot->type_map) and
 * give types without a mass the potential's mass; errors name the type. */
int potential_bind(struct potential *pot, struct particles *p, struct err *e);

/* Resolve a potential file name to a readable path: as a path (see
 * cfg_find_file), then in $CASCADE_POTENTIALS, then in Debian's
 * /usr/share/lammps/potentials.  Returns 0 or -1. */
int potential_find_file(const struct cfg *c, const char *name, char *path, size_t len);

/* Read the `file` key of a potential section and find it; in shallow mode
 * only the key is checked.  Errors name the key. */
int potential_file_key(struct cfg_obj *o, char *path, size_t len);


/* The registry. */
struct potential_style {
    const char *name;
    const char *summary;
    int (*create)(struct cfg_obj *o, struct potential **out);
};
extern const struct potential_style potential_styles[];   /* NULL-name terminated */

#endif
