/* locmap: open-addressing hash table from document path to source location. */
#include "util/locmap.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "util/mem.h"

struct locmap_slot {
    char *path;
    struct loc loc;
};

struct locmap {
    size_t cap, count;     /* cap is a power of two */
    struct locmap_slot *slots;
};

static uint64_t path_hash(const char *s)
{
    uint64_t h = 1469598103934665603ull;   /* FNV-1a */
    for (; *s; s++) {
        h ^= (unsigned char)*s;
        h *= 1099511628211ull;
    }
    return h;
}

struct locmap *locmap_create(void)
{
    struct locmap *m = mem_calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->cap = 64;
    m->slots = mem_calloc(m->cap, sizeof *m->slots);
    if (!m->slots) {
        free(m);
        return NULL;
    }
    return m;
}

void locmap_destroy(struct locmap **pm)
{
    struct locmap *m = pm ? *pm : NULL;
    if (!m)
        return;
    for (size_t i = 0; i < m->cap; i++)
        free(m->slots[i].path);
    free(m->slots);
    free(m);
    *pm = NULL;
}

static struct locmap_slot *find_slot(struct locmap_slot *slots, size_t cap, const char *path)
{
    size_t i = path_hash(path) & (cap - 1);
    while (slots[i].path && strcmp(slots[i].path, path) != 0)
        i = (i + 1) & (cap - 1);
    return &slots[i];
}

static int grow(struct locmap *m)
{
    size_t ncap = m->cap * 2;
    struct locmap_slot *ns = mem_calloc(ncap, sizeof *ns);
    if (!ns)
        return -1;
    for (size_t i = 0; i < m->cap; i++)
        if (m->slots[i].path)
            *find_slot(ns, ncap, m->slots[i].path) = m->slots[i];
    free(m->slots);
    m->slots = ns;
    m->cap = ncap;
    return 0;
}

int locmap_put(struct locmap *m, const char *path, struct loc loc)
{
    if (2 * (m->count + 1) > m->cap && grow(m) != 0)
        return -1;
    struct locmap_slot *s = find_slot(m->slots, m->cap, path);
    if (!s->path) {
        s->path = mem_strdup(path);
        if (!s->path)
            return -1;
        m->count++;
    }
    s->loc = loc;
    return 0;
}

const struct loc *locmap_get(const struct locmap *m, const char *path)
{
    if (!m)
        return NULL;
    struct locmap_slot *s = find_slot(m->slots, m->cap, path);
    return s->path ? &s->loc : NULL;
}
