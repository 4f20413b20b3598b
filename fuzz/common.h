/*
 * common: what the fuzz harnesses share -- a scratch directory per input,
 * writing the input into it, and building a potential from a file the way
 * a case's `potential` section does (then one force evaluation on a few
 * atoms at fixed, physically plausible distances).
 */
#ifndef CASCADE_FUZZ_COMMON_H
#define CASCADE_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

#define FUZZ_PATH_MAX 512

/* A new empty directory under $TMPDIR (or /tmp); aborts when it cannot. */
void fuzz_dir_create(char *dir, size_t len);
/* Remove the files fuzz_write put in it, and the directory. */
void fuzz_dir_remove(const char *dir);

/* Write bytes to dir/name; path receives the full name.  Aborts on I/O
 * errors (the harness, not the reader, failed). */
void fuzz_write(const char *dir, const char *name, const void *data, size_t size, char *path,
                size_t len);

/* A NUL-terminated copy of the input (malloc'ed). */
char *fuzz_text(const uint8_t *data, size_t size);

/* The reader failed: its message must say something.  Aborts otherwise.
 * With CASCADE_FUZZ_VERBOSE set in the environment the message is printed
 * (to see why a corpus file is rejected). */
void fuzz_check_error(int rc, const char *msg);

/* potential: {style: STYLE, file: PATH, elements: [...], masses: [...]}
 * (elements omitted when nelements is 0, masses when masses is NULL),
 * created with potential_create; when that works, forces and energies of a
 * small cluster are computed once. */
void fuzz_potential(const char *style, const char *path, const char *const *elements,
                    const double *masses, int nelements);

#endif
