/* mem: libc allocation behind an allocation fault point (mem.h). */
#include "util/mem.h"

#include <stdlib.h>
#include <string.h>

#include "util/fault.h"

void *mem_alloc(size_t n)
{
    return fault_alloc_fails() ? NULL : malloc(n);
}

void *mem_calloc(size_t n, size_t size)
{
    return fault_alloc_fails() ? NULL : calloc(n, size);
}

void *mem_realloc(void *p, size_t n)
{
    return fault_alloc_fails() ? NULL : realloc(p, n);
}

char *mem_strdup(const char *s)
{
    return fault_alloc_fails() ? NULL : strdup(s);
}

char *mem_strndup(const char *s, size_t n)
{
    return fault_alloc_fails() ? NULL : strndup(s, n);
}
