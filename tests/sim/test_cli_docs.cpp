// SPDX-License-Identifier: MIT
// pce-sim's command line against its documentation. The options `pce-sim --help` lists are
// exactly those of docs/simulation.md §1's usage block and of its options table (either
// side's extra option fails, naming it). Every pce-sim command line the documentation shows
// (docs/*.md and README.md: lines of fenced and indented code blocks, and inline code spans,
// that start with `pce-sim`, `./build/src/sim/pce-sim` or `build/src/sim/pce-sim`) runs:
// with `--frames 1 --no-frames --out <a folder of the build>` appended (and `--video` and
// `--usd` into that folder when it has them; the last value of a repeated option wins), from
// the source directory, it must exit with 0 after one frame.
// Command lines that are templates are skipped: those with a placeholder in capitals
// (SCENE.json, DIR, N, RESULTS/…), "…", "...", brackets or alternatives (`[--a | --b]`).
// Each runs one frame only, so the cost is the scene's loading and first step: every scene
// the documentation names in a command loads and steps in well under a second here; the
// largest shipped scene, examples/scenes/drop_130k.json, appears in no command line.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs `command` (a shell command line) from the source directory; returns the exit code
/// and the captured stdout and stderr in `output`.
int run_in_source_dir(const std::string& command, std::string* output) {
  static int calls = 0;
  const fs::path log =
      fs::path(PCE_TEST_TMP) / ("cli_docs_" + std::to_string(getpid()) + "_" + std::to_string(calls++) + ".txt");
  const std::string line = "cd '" + std::string(PCE_SOURCE_DIR) + "' && " + command + " > " + log.string() + " 2>&1";
  const int status = std::system(line.c_str());
  *output = read_text(log);
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string join(const std::set<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// The long options (`--name`) in `text`, and `-h` written as `-h` (its short form).
std::set<std::string> options_in(const std::string& text) {
  static const std::regex option("(^|[^-a-z0-9])(--[a-z][a-z0-9-]*)");
  std::set<std::string> out;
  for (std::sregex_iterator it(text.begin(), text.end(), option), e; it != e; ++it) out.insert((*it)[2]);
  return out;
}

/// docs/simulation.md §1 ("## 1. Quick start" to "## 2.").
std::string quick_start() {
  const std::string doc = read_text(fs::path(PCE_SOURCE_DIR) / "docs" / "simulation.md");
  const std::size_t b = doc.find("\n## 1. Quick start\n"), e = doc.find("\n## 2. ", b);
  return b == std::string::npos || e == std::string::npos ? "" : doc.substr(b, e - b);
}

TEST(CliDocs, HelpListsExactlyTheDocumentedOptions) {
  std::string help;
  ASSERT_EQ(run_in_source_dir(std::string(PCE_SIM_EXE) + " --help", &help), 0) << help;
  // The options of --help: the first word of each line of its "Options:" part.
  std::set<std::string> cli;
  std::stringstream lines(help.substr(help.find("Options:")));
  std::string line;
  static const std::regex first("^\\s+(-h,)?(--[a-z][a-z0-9-]*)");
  while (std::getline(lines, line)) {
    std::smatch m;
    if (std::regex_search(line, m, first)) cli.insert(m[2]);
  }
  ASSERT_GE(cli.size(), 10u) << "no options parsed from pce-sim --help:\n" << help;

  const std::string section = quick_start();
  ASSERT_FALSE(section.empty()) << "docs/simulation.md has no section \"## 1. Quick start\"";
  // The usage block: the indented lines that follow "The binary is".
  std::string usage;
  {
    std::stringstream in(section.substr(section.find("The binary is")));
    bool started = false;
    while (std::getline(in, line)) {
      const bool code = line.rfind("    ", 0) == 0;
      if (code) started = true, usage += line + "\n";
      if (started && !code) break;
    }
  }
  ASSERT_FALSE(usage.empty()) << "docs/simulation.md §1: no usage block after \"The binary is\"";
  // The options table: its rows' first cells.
  std::string table;
  {
    std::stringstream in(section.substr(section.find("| option | meaning |")));
    while (std::getline(in, line) && line.rfind("|", 0) == 0) table += line.substr(0, line.find(" | ", 1)) + "\n";
  }
  const std::set<std::string> in_usage = options_in(usage), in_table = options_in(table);
  for (const auto& [name, documented] :
       {std::pair<const char*, const std::set<std::string>&>{"usage block", in_usage}, {"options table", in_table}}) {
    for (const std::string& o : cli)
      EXPECT_TRUE(documented.count(o)) << "pce-sim --help lists " << o << ", which docs/simulation.md §1's " << name
                                       << " lacks (it lists: " << join(documented) << ")";
    for (const std::string& o : documented)
      EXPECT_TRUE(cli.count(o)) << "docs/simulation.md §1's " << name << " lists " << o
                                << ", which pce-sim --help does not (it lists: " << join(cli) << ")";
  }
}

/// A documented command line: where it is shown and its words.
struct Shown {
  std::string where;  ///< file:line
  std::vector<std::string> words;
};

/// The words of `text` (split at white space).
std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string w;
  while (in >> w) out.push_back(w);
  return out;
}

bool is_pce_sim(const std::string& word) {
  return word == "pce-sim" || word == "./build/src/sim/pce-sim" || word == "build/src/sim/pce-sim";
}

/// The pce-sim command lines shown in `file` (see the file's comment), each with its line.
std::vector<Shown> shown_in(const fs::path& file, const std::string& name) {
  std::vector<Shown> out;
  std::stringstream in(read_text(file));
  std::string line, paragraph;
  int number = 0, paragraph_start = 0;
  bool fenced = false;
  auto take = [&](const std::string& text, int at) {
    std::vector<std::string> w = words_of(text);
    if (w.size() >= 2 && is_pce_sim(w[0])) out.push_back({name + ":" + std::to_string(at), w});
  };
  auto spans = [&]() {  // the inline code spans of the paragraph
    for (std::size_t b = paragraph.find('`'); b != std::string::npos; b = paragraph.find('`', b + 1)) {
      const std::size_t e = paragraph.find('`', b + 1);
      if (e == std::string::npos) break;
      const std::string span = paragraph.substr(b + 1, e - b - 1);
      const int at = paragraph_start + static_cast<int>(std::count(paragraph.begin(), paragraph.begin() + b, '\n'));
      take(span, at);
      b = e;
    }
    paragraph.clear();
  };
  std::string continued;  // a code line ending in a backslash, joined with the next
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      spans();
      continue;
    }
    const bool indented = !fenced && line.rfind("    ", 0) == 0 && paragraph.empty();
    if (fenced || indented) {
      if (!line.empty() && line.back() == '\\') {
        continued += line.substr(0, line.size() - 1) + " ";
        continue;
      }
      take(continued + line, number);
      continued.clear();
      continue;
    }
    if (line.find_first_not_of(" \t") == std::string::npos) {
      spans();
      continue;
    }
    if (paragraph.empty()) paragraph_start = number;
    paragraph += line + "\n";
  }
  spans();
  return out;
}

/// Why `words` are a template and not a command line to run, or "".
std::string template_reason(const std::vector<std::string>& words) {
  static const std::regex capitals("(^|[/=])[A-Z][A-Z0-9_]*(\\.[a-z]+)?($|/)");
  for (std::size_t k = 1; k < words.size(); ++k) {
    const std::string& w = words[k];
    if (std::regex_search(w, capitals)) return "placeholder " + w;
    for (const char* mark : {"...", "…", "[", "]", "|", "<", ">", "$", "*"})
      if (w.find(mark) != std::string::npos) return std::string("\"") + mark + "\" in " + w;
  }
  return "";
}

std::vector<Shown> documented_command_lines() {
  std::vector<Shown> all;
  std::vector<fs::path> files{fs::path(PCE_SOURCE_DIR) / "README.md"};
  for (const auto& entry : fs::directory_iterator(fs::path(PCE_SOURCE_DIR) / "docs"))
    if (entry.path().extension() == ".md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    const std::string name = fs::relative(f, PCE_SOURCE_DIR).string();
    for (Shown& s : shown_in(f, name)) all.push_back(std::move(s));
  }
  return all;
}

TEST(CliDocs, EveryDocumentedCommandLineRuns) {
  const std::vector<Shown> shown = documented_command_lines();
  int ran = 0;
  for (const Shown& s : shown) {
    std::string command;
    for (const auto& w : s.words) command += (command.empty() ? "" : " ") + w;
    if (std::find(s.words.begin(), s.words.end(), "--help") != s.words.end()) {
      std::cout << "skipped (--help: HelpListsExactlyTheDocumentedOptions runs it): " << s.where << "\n";
      continue;
    }
    const std::string why = template_reason(s.words);
    if (!why.empty()) {
      std::cout << "skipped (template: " << why << "): " << s.where << ": " << command << "\n";
      continue;
    }
    const fs::path out = fs::path(PCE_TEST_TMP) / ("cli_docs_run_" + std::to_string(ran++));
    fs::remove_all(out);
    std::string args;
    for (std::size_t k = 1; k < s.words.size(); ++k) args += " '" + s.words[k] + "'";
    // A movie or a cache the command writes goes into the folder too (nothing is written
    // into the source tree).
    std::string outputs;
    if (std::find(s.words.begin(), s.words.end(), "--video") != s.words.end())
      outputs += " --video '" + (out / "movie.mp4").string() + "'";
    if (std::find(s.words.begin(), s.words.end(), "--usd") != s.words.end())
      outputs += " --usd '" + (out / "cache.usda").string() + "'";
    std::string output;
    const int code = run_in_source_dir(
        std::string(PCE_SIM_EXE) + args + " --frames 1 --no-frames --out '" + out.string() + "'" + outputs, &output);
    std::cout << "ran (exit " << code << "): " << s.where << ": " << command << "\n";
    EXPECT_EQ(code, 0) << s.where << ": `" << command << "` (run with --frames 1 --no-frames --out DIR) failed:\n"
                       << output;
    EXPECT_TRUE(fs::exists(out / "stats.jsonl")) << s.where << ": " << command;
    fs::remove_all(out);
  }
  // The documentation shows at least these (so that a broken parse cannot pass unseen).
  EXPECT_GE(ran, 5) << "fewer documented pce-sim command lines ran than expected";
}

}  // namespace
