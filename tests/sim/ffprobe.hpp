// SPDX-License-Identifier: MIT
// The movie tests' probe (test_output.cpp, test_pce_sim.cpp): what ffprobe says of a movie's
// video stream, frames counted, and whether ffmpeg and ffprobe are both there to ask.
#pragma once

#include <pce/sim/movie.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

namespace pce::sim::testing {

/// `key=value` lines of ffprobe about `file`'s video stream, frames counted (empty if
/// ffprobe fails).
inline std::map<std::string, std::string> probe(const std::filesystem::path& file) {
  const std::string command =
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=codec_name,pix_fmt,width,height,r_frame_rate,nb_read_frames -of default=nw=1 '" +
      file.string() + "'";
  std::map<std::string, std::string> out;
  std::FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  char line[256];
  while (std::fgets(line, sizeof line, pipe)) {
    std::string s(line);
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    const std::size_t eq = s.find('=');
    if (eq != std::string::npos) out[s.substr(0, eq)] = s.substr(eq + 1);
  }
  pclose(pipe);
  return out;
}

/// Whether ffmpeg (as pce-sim finds it) and ffprobe are on PATH.
inline bool have_ffmpeg_and_ffprobe() {
  return !find_ffmpeg().empty() && std::system("command -v ffprobe > /dev/null 2>&1") == 0;
}

}  // namespace pce::sim::testing
