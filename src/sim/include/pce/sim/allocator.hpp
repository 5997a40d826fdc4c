// SPDX-License-Identifier: MIT
/// @file
/// The process's memory allocator, tuned for the linear solve (docs/simulation.md, "Speed").
///
/// CHOLMOD allocates its factor afresh at every symbolic analysis (a few times per Newton
/// step in contact) and its workspace at every factorisation. On the hammock the factor
/// holds 3.5–7 M non-zeros, 28–56 MB: glibc serves blocks that large with `mmap` and
/// returns them to the kernel when they are freed, so every factorisation writes into fresh
/// pages, which the kernel must fault in and zero. `keep_freed_memory` makes glibc serve
/// every block from its heap and never trim the heap, so freed blocks are reused: on the
/// hammock's frames 21–30 (one thread) page faults fell from 712 k to 71 k and kernel time
/// from 2.1 to 0.55 s (docs/simulation.md §5.3). The price is that a process keeps its
/// peak heap until it exits.
///
/// It changes a process-wide setting, so `pce::sim` never calls it: `pce-sim` calls it
/// first thing, and a program that links `pce::sim` may do the same.
#pragma once

namespace pce::sim {

/// Sets glibc's `M_MMAP_MAX` to 0 (no block is served by `mmap`) and `M_TRIM_THRESHOLD`
/// to its largest value (the heap is never given back). Returns true when both settings
/// took; false where the C library is not glibc (nothing is changed there).
bool keep_freed_memory();

}  // namespace pce::sim
