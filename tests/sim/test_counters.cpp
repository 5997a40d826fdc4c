// SPDX-License-Identifier: MIT
// pce/sim/counters.hpp: typed frame counters. Reported counters merge by their rule (sum, or
// the minimum for distances), absent ones stay absent, names are the stats.json keys (each
// enumerator's identifier, every one documented in docs/simulation.md §6.1), and asking for
// an unreported or unknown counter throws.
#include <pce/sim/counters.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

using pce::sim::Counter;
using pce::sim::Counters;

TEST(Counters, MergeSumsCountsAndKeepsTheSmallestDistance) {
  Counters vf, ee, frame;
  vf[Counter::vertex_face_contacts] = 3;
  vf[Counter::vertex_face_min_distance] = 0.5;
  vf[Counter::broad_phase_ms] = 2;
  ee[Counter::edge_edge_contacts] = 4;
  ee[Counter::broad_phase_ms] = 5;
  Counters obstacles;
  obstacles[Counter::obstacle_min_distance] = 0.25;
  Counters more;
  more[Counter::vertex_face_min_distance] = 0.75;  // larger: the minimum stays 0.5
  more[Counter::vertex_face_contacts] = 1;
  for (const Counters* c : {&vf, &ee, &obstacles, &more}) frame.merge(*c);
  EXPECT_EQ(frame.at(Counter::vertex_face_contacts), 4);
  EXPECT_EQ(frame.at(Counter::edge_edge_contacts), 4);
  EXPECT_EQ(frame.at(Counter::broad_phase_ms), 7);
  EXPECT_EQ(frame.at(Counter::vertex_face_min_distance), 0.5);
  EXPECT_EQ(frame.at("obstacle_min_distance"), 0.25);
  EXPECT_FALSE(frame.has(Counter::hinges));
  EXPECT_FALSE(frame.has("hinges"));
  EXPECT_THROW(frame.at(Counter::hinges), std::out_of_range);
  EXPECT_THROW(frame.at("no_such_counter"), std::out_of_range);
  EXPECT_EQ(frame.entries().size(), 5u);
  EXPECT_STREQ(frame.entries().front().first, "vertex_face_contacts");  // enumerator order
}

TEST(Counters, EveryCounterHasItsOwnName) {
  std::set<std::string> names;
  for (int i = 0; i < static_cast<int>(Counter::count); ++i) {
    const char* name = pce::sim::counter_info(static_cast<Counter>(i)).name;
    ASSERT_NE(name, nullptr);
    EXPECT_TRUE(names.insert(name).second) << name;
    // only the minimum distances merge by their minimum
    EXPECT_EQ(pce::sim::counter_info(static_cast<Counter>(i)).minimum, std::strstr(name, "min_distance") != nullptr)
        << name;
  }
}

TEST(Counters, EachEnumeratorIsNamedByItsIdentifier) {
  int listed = 0;
  // Every entry of the list: the enumerator's name is its identifier, at its own index.
#define PCE_TEST_COUNTER_NAME(id, rule)                                                    \
  EXPECT_STREQ(pce::sim::counter_info(Counter::id).name, #id);                             \
  EXPECT_EQ(static_cast<int>(Counter::id), listed);                                        \
  EXPECT_EQ(pce::sim::counter_info(Counter::id).minimum, std::string(#rule) == "minimum"); \
  ++listed;
  PCE_SIM_COUNTERS(PCE_TEST_COUNTER_NAME)
#undef PCE_TEST_COUNTER_NAME
  EXPECT_EQ(listed, static_cast<int>(Counter::count));
}

TEST(Counters, EveryNameIsDocumentedInStatsJsonSection) {
  std::ifstream in(std::string(PCE_SOURCE_DIR) + "/docs/simulation.md");
  ASSERT_TRUE(in) << "docs/simulation.md";
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const std::size_t begin = doc.find("### 6.1 "), end = doc.find("### 6.2 ");
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  const std::string section = doc.substr(begin, end - begin);
  for (int i = 0; i < static_cast<int>(Counter::count); ++i) {
    const std::string name = pce::sim::counter_info(static_cast<Counter>(i)).name;
    EXPECT_NE(section.find("`" + name + "`"), std::string::npos)
        << name << " is not documented in docs/simulation.md section 6.1";
  }
}
