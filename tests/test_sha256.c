/*
 * SHA-256 (util/sha256.h, on Nettle): the FIPS 180-2 example digests, and
 * files of lengths around the 64-byte block and the 56-byte padding limit
 * against coreutils' sha256sum -- the digests recorded in databases (job
 * keys, artifact checksums, baseline hashes) must not change with the
 * implementation.
 */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "helpers/ct.h"
#include "util/canon.h"
#include "util/sha256.h"

Test(sha256, fips_examples)
{
    char hex[65];
    sha256_hex("abc", 3, hex);
    cr_assert_str_eq(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    sha256_hex("", 0, hex);
    cr_assert_str_eq(hex, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const char *m = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    sha256_hex(m, strlen(m), hex);
    cr_assert_str_eq(hex, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    size_t n = 1000000;
    char *a = malloc(n);
    cr_assert_not_null(a);
    memset(a, 'a', n);
    sha256_hex(a, n, hex);
    cr_assert_str_eq(hex, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    free(a);
    /* a job key: the first 16 hex digits of the canonical text's digest */
    json_t *v = json_loads("{\"b\": [2.5, \"x\"], \"a\": 1}", 0, NULL);
    char key[CANON_KEY_LEN + 1];
    canon_key(v, key);
    char *text = canon_json(v);
    cr_assert_str_eq(text, "{\"a\":1,\"b\":[2.5,\"x\"]}");
    sha256_hex(text, strlen(text), hex);
    cr_assert_eq(strncmp(key, hex, CANON_KEY_LEN), 0, "%s %s", key, hex);
    free(text);
    json_decref(v);
}

Test(sha256, files_agree_with_sha256sum)
{
    char dir[64];
    ct_mkdir(dir, sizeof dir);
    static const size_t lens[] = {0, 1, 55, 56, 57, 63, 64, 65, 119, 120, 128, 65535, 65536,
                                  65537, 1000003};
    unsigned s = 7;
    for (size_t k = 0; k < sizeof lens / sizeof lens[0]; k++) {
        char path[128];
        snprintf(path, sizeof path, "%s/f%zu.bin", dir, k);
        FILE *f = fopen(path, "wb");
        cr_assert_not_null(f);
        for (size_t i = 0; i < lens[k]; i++) {
            s = s * 1103515245u + 12345u;
            fputc((int)(s >> 16) & 0xff, f);
        }
        fclose(f);
        char hex[65], out[512];
        uint64_t bytes = 99;
        cr_assert_eq(sha256_file_hex(path, hex, &bytes), 0);
        cr_assert_eq(bytes, lens[k]);
        const char *argv[] = {"/usr/bin/sha256sum", path, NULL};
        cr_assert_eq(ct_exec(dir, NULL, argv, out, sizeof out), 0, "%s", out);
        cr_assert_eq(strncmp(out, hex, 64), 0, "%zu bytes: sha256sum %.64s, ours %s", lens[k], out,
                     hex);
    }
    char hex[65];
    cr_assert_eq(sha256_file_hex("/nonexistent/file", hex, NULL), -1);
    ct_rmrf(dir);
}
