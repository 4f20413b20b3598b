/* sha256: FIPS 180-4 SHA-256, for job keys and artifact checksums. */
#ifndef CASCADE_SHA256_H
#define CASCADE_SHA256_H

#include <stddef.h>
#include <stdint.h>

struct sha256 {
    uint32_t h[8];
    uint64_t nbytes;
    unsigned char buf[64];
    size_t nbuf;
};

void sha256_init(struct sha256 *s);
void sha256_update(struct sha256 *s, const void *data, size_t len);
void sha256_final(struct sha256 *s, unsigned char digest[32]);
/* Hex digest (65 bytes with the terminator) of a buffer. */
void sha256_hex(const void *data, size_t len, char hex[65]);
/* Hex digest of a file; returns 0 or -1 (cannot read). */
int sha256_file_hex(const char *path, char hex[65], uint64_t *nbytes);

#endif
