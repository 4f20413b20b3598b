/* sha256: hex digests on Nettle's SHA-256 (a maintained implementation that
 * uses the CPU's SHA extensions where it has them). */
#include "util/sha256.h"

#include <nettle/sha2.h>
#include <stdio.h>

static void to_hex(const unsigned char d[SHA256_DIGEST_SIZE], char hex[65])
{
    static const char digits[] = "0123456789abcdef";
    for (int i = 0; i < SHA256_DIGEST_SIZE; i++) {
        hex[2 * i] = digits[d[i] >> 4];
        hex[2 * i + 1] = digits[d[i] & 15];
    }
    hex[64] = '\0';
}

void sha256_hex(const void *data, size_t len, char hex[65])
{
    struct sha256_ctx s;
    unsigned char d[SHA256_DIGEST_SIZE];
    sha256_init(&s);
    sha256_update(&s, len, data);
    sha256_digest(&s, sizeof d, d);
    to_hex(d, hex);
}

int sha256_file_hex(const char *path, char hex[65], uint64_t *nbytes)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    struct sha256_ctx s;
    unsigned char buf[65536], d[SHA256_DIGEST_SIZE];
    uint64_t total = 0;
    sha256_init(&s);
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, f)) > 0) {
        sha256_update(&s, got, buf);
        total += got;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad)
        return -1;
    if (nbytes)
        *nbytes = total;
    sha256_digest(&s, sizeof d, d);
    to_hex(d, hex);
    return 0;
}
