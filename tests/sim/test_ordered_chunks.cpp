// SPDX-License-Identifier: MIT
// The chunked passes of src/sim/effects/contact/ordered_chunks.hpp: min_over_chunks hands
// every chunk a running minimum that starts at `start`, whichever thread runs it and
// whatever that thread ran before, so what a body records on the way (the step bounds'
// held pairs: those whose limit was below the running minimum) is the same for one thread
// and for two. (A running minimum per thread, as before, started at +inf on a worker
// thread and carried one chunk's minimum into the next: two runs of one step could hold
// different pairs, and an 8 K-vertex drape with two threads ended its 12th frame in 26 or
// 27 Newton iterations from one run to the next.)
#include "effects/contact/ordered_chunks.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <vector>

namespace {

using pce::sim::contact::chunk_count;
using pce::sim::contact::min_over_chunks;

/// A pass over n values v_k = a pseudo-random number in (0, 1): each chunk records the
/// running minimum it was handed and the indices whose value was below its running
/// minimum as it came to them (what the step bounds record), and lowers the minimum.
struct Pass {
  std::vector<double> handed;
  std::vector<std::vector<long>> below;
  double result = 0;
};

Pass run(int threads, long n, long chunk, double start) {
  Pass p;
  const std::size_t chunks = chunk_count(n, chunk);
  p.handed.assign(chunks, -1.0);
  p.below.assign(chunks, {});
  const auto value = [](long k) { return 0.5 + 0.5 * std::sin(12.9898 * static_cast<double>(k) + 3.0); };
  omp_set_num_threads(threads);
  p.result = min_over_chunks(n, chunk, start, [&](std::size_t c, long begin, long end, double& t) {
    p.handed[c] = t;
    for (long k = begin; k < end; ++k)
      if (value(k) < t) {
        p.below[c].push_back(k);
        t = value(k);
      }
  });
  omp_set_num_threads(omp_get_num_procs());
  return p;
}

TEST(OrderedChunks, EveryChunkStartsFromTheStartWhateverTheThreadCount) {
  const long n = 100000, chunk = 64;
  for (double start : {1.0, 0.3}) {
    const Pass one = run(1, n, chunk, start), two = run(2, n, chunk, start);
    for (std::size_t c = 0; c < one.handed.size(); ++c) {
      ASSERT_EQ(one.handed[c], start) << "chunk " << c << ", one thread";
      ASSERT_EQ(two.handed[c], start) << "chunk " << c << ", two threads";
    }
    EXPECT_EQ(one.below, two.below);
    EXPECT_EQ(one.result, two.result);
    EXPECT_LT(one.result, 1e-6);  // the smallest value, found whichever thread ran its chunk
  }
  EXPECT_EQ(run(2, 0, chunk, 0.7).result, 0.7);  // no chunk: the start
}

}  // namespace
