// SPDX-License-Identifier: MIT
/// @file
/// `pce-fuzz-libfuzzer`: the libFuzzer entry point over the fuzz body (clang only, built
/// with -fsanitize=fuzzer,address,undefined). See docs/fuzzing.md.
#include "fuzz_pair.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) { return pce_fuzz_one(data, size); }
