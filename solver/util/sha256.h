/* sha256: SHA-256 (FIPS 180-4) hex digests for job keys and artifact
 * checksums, computed by Nettle (Debian's nettle-dev). */
#ifndef CASCADE_SHA256_H
#define CASCADE_SHA256_H

#include <stddef.h>
#include <stdint.h>

/* Hex digest (65 bytes with the terminator) of a buffer. */
void sha256_hex(const void *data, size_t len, char hex[65]);
/* Hex digest of a file; returns 0 or -1 (cannot read). */
int sha256_file_hex(const char *path, char hex[65], uint64_t *nbytes);

#endif
