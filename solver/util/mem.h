/*
 * mem: the allocation functions Cascade's own code calls instead of libc's,
 * so CASCADE_FAULT_ALLOC (util/fault.h) can fail the Nth of them.  Each
 * behaves exactly like its libc namesake (NULL on failure, free() to
 * release); when no fault is installed the only extra cost is one branch.
 * Memory allocated inside libraries (SQLite, jansson, libyaml, HDF5) does
 * not pass here.
 */
#ifndef CASCADE_MEM_H
#define CASCADE_MEM_H

#include <stddef.h>

void *mem_alloc(size_t n);
void *mem_calloc(size_t n, size_t size);
void *mem_realloc(void *p, size_t n);
char *mem_strdup(const char *s);
char *mem_strndup(const char *s, size_t n);

#endif
