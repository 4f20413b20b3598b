/*
 * fuzz: one harness per input reader (docs/fuzzing.md).
 *
 * Each fuzz/fuzz_<reader>.c defines fuzz_<reader>_one(), which feeds one
 * input to the reader the way the programs do (through a temporary file
 * where the reader takes a path), uses what it returns a little, and frees
 * everything.  It returns 0; a bug shows as a crash or a sanitizer report.
 * Built with -DCASCADE_LIBFUZZER the file also defines libFuzzer's entry
 * point (make fuzz); without it the functions are linked into the test
 * binary, which replays the corpora (tests/test_fuzz_corpus.c).
 */
#ifndef CASCADE_FUZZ_H
#define CASCADE_FUZZ_H

#include <stddef.h>
#include <stdint.h>

int fuzz_case_one(const uint8_t *data, size_t size);
int fuzz_study_one(const uint8_t *data, size_t size);
int fuzz_lammps_data_one(const uint8_t *data, size_t size);
int fuzz_extxyz_one(const uint8_t *data, size_t size);
int fuzz_eam_one(const uint8_t *data, size_t size);
int fuzz_sw_one(const uint8_t *data, size_t size);
int fuzz_meam_spline_one(const uint8_t *data, size_t size);
int fuzz_result_json_one(const uint8_t *data, size_t size);
int fuzz_baseline_one(const uint8_t *data, size_t size);

#ifdef CASCADE_LIBFUZZER
#define FUZZ_ENTRY(name)                                                                          \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);                                 \
    int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)                                  \
    {                                                                                             \
        fuzz_##name##_one(data, size);                                                            \
        return 0;                                                                                 \
    }
#else
#define FUZZ_ENTRY(name)
#endif

#endif
