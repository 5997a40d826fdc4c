// SPDX-License-Identifier: MIT
// The movie of a run (pce/sim/movie.hpp): one camera fitted to every recorded frame, each
// frame rendered and piped as raw RGB to an ffmpeg child process that encodes H.264.
#include <pce/sim/frames.hpp>
#include <pce/sim/movie.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

extern char** environ;

namespace pce::sim {

namespace fs = std::filesystem;

const std::vector<std::string>& movie_extensions() {
  static const std::vector<std::string> extensions{".mp4", ".m4v", ".mov", ".mkv"};
  return extensions;
}

fs::path find_ffmpeg() {
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/local/bin:/usr/bin:/bin";
  std::size_t begin = 0;
  while (begin <= path.size()) {
    const std::size_t end = std::min(path.find(':', begin), path.size());
    // An empty entry is the current directory, as for execvp.
    const fs::path dir = end == begin ? fs::path(".") : fs::path(path.substr(begin, end - begin));
    const fs::path candidate = dir / "ffmpeg";
    std::error_code error;
    if (fs::is_regular_file(candidate, error) && access(candidate.c_str(), X_OK) == 0) return candidate;
    begin = end + 1;
  }
  return {};
}

std::string ffmpeg_missing() { return "ffmpeg not found on PATH; install it (Debian, Ubuntu: apt-get install ffmpeg)"; }

Eigen::Vector3f mesh_color(std::size_t k) {
  static const Eigen::Vector3f palette[] = {{0.85f, 0.35f, 0.25f}, {0.25f, 0.55f, 0.85f}, {0.35f, 0.70f, 0.35f},
                                            {0.90f, 0.70f, 0.20f}, {0.60f, 0.40f, 0.75f}, {0.30f, 0.70f, 0.70f}};
  return palette[k % 6];
}

std::vector<RenderMesh> scene_picture(const Scene& scene, const Eigen::Matrix3Xd& x, double time) {
  const Simulation& sim = scene.simulation;
  std::vector<RenderMesh> meshes;
  std::size_t k = 0;
  for (const MeshRange& r : sim.model.meshes) {
    RenderMesh m;
    m.positions = x.middleCols(r.first_vertex, r.vertex_count);
    m.triangles = sim.model.triangles.middleCols(r.first_triangle, r.triangle_count).array() - r.first_vertex;
    m.segments = sim.model.segments.middleCols(r.first_segment, r.segment_count).array() - r.first_vertex;
    m.color = mesh_color(k++);
    meshes.push_back(std::move(m));
  }
  for (const Obstacle& o : sim.obstacles) {
    const Mesh s = surface_mesh(o, o.pose(time));
    RenderMesh m;
    m.positions = s.positions;
    m.triangles = s.triangles;
    m.color = Eigen::Vector3f(0.62f, 0.62f, 0.66f);
    meshes.push_back(std::move(m));
  }
  return meshes;
}

namespace {

/// The ffmpeg child: its pid, the write end of its standard input, its log file.
class Encoder {
 public:
  Encoder(const fs::path& ffmpeg, const fs::path& movie, const fs::path& log, const RenderOptions& picture,
          double frame_rate)
      : movie_(movie), log_(log) {
    char rate[64];
    std::snprintf(rate, sizeof rate, "%.9g", frame_rate);
    std::string ending = movie.extension().string();
    for (char& c : ending) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::vector<std::string> args{ffmpeg.string(),
                                  "-hide_banner",
                                  "-nostdin",
                                  "-loglevel",
                                  "error",
                                  "-y",
                                  "-f",
                                  "rawvideo",
                                  "-pixel_format",
                                  "rgb24",
                                  "-video_size",
                                  std::to_string(picture.width) + "x" + std::to_string(picture.height),
                                  "-framerate",
                                  rate,
                                  "-i",
                                  "pipe:0",
                                  "-an",
                                  "-c:v",
                                  "libx264",
                                  "-pix_fmt",
                                  "yuv420p"};
    if (ending != ".mkv") args.insert(args.end(), {"-movflags", "+faststart"});
    // "file:" and an absolute path: a name with a colon or a leading '-' is still a file.
    args.push_back("file:" + fs::absolute(movie).string());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);

    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) fail(std::string("cannot make a pipe (") + std::strerror(errno) + ")");
    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attributes;
    posix_spawn_file_actions_init(&actions);
    posix_spawnattr_init(&attributes);
    posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    // Its own process group (a Ctrl-C at the terminal is pce-sim's to handle, not ffmpeg's),
    // no blocked signals and the default actions for those a caller may have changed.
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (const int s : {SIGPIPE, SIGINT, SIGTERM}) sigaddset(&defaults, s);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
    const int spawned = posix_spawn(&pid_, argv[0], &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    close(fds[0]);
    if (spawned != 0) {
      close(fds[1]);
      pid_ = -1;
      fail("cannot start " + ffmpeg.string() + " (" + std::strerror(spawned) + ")");
    }
    in_ = fds[1];
  }

  ~Encoder() {
    if (in_ >= 0) close(in_);
    if (pid_ > 0) {
      int status = 0;
      while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
      }
    }
    std::error_code ignored;
    fs::remove(log_, ignored);
  }
  Encoder(const Encoder&) = delete;
  Encoder& operator=(const Encoder&) = delete;

  /// Writes one frame's pixels; false if ffmpeg no longer reads (it ended).
  bool write(const std::vector<std::uint8_t>& pixels) {
    // SIGPIPE is blocked while writing, so that an ffmpeg that has ended gives EPIPE (and
    // its own message, from `finish`) instead of ending this process; a SIGPIPE raised
    // meanwhile is taken before the mask is restored.
    sigset_t pipe_signal, previous;
    sigemptyset(&pipe_signal);
    sigaddset(&pipe_signal, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
    const std::uint8_t* p = pixels.data();
    std::size_t left = pixels.size();
    bool broken = false;
    while (left > 0) {
      const ssize_t n = ::write(in_, p, left);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        broken = true;
        break;
      }
      p += n, left -= static_cast<std::size_t>(n);
    }
    if (broken) {
      const timespec now{0, 0};
      sigtimedwait(&pipe_signal, nullptr, &now);
    }
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    return !broken;
  }

  /// Closes ffmpeg's input and waits for it; throws with its messages unless it succeeded.
  void finish() {
    close(in_);
    in_ = -1;
    int status = 0;
    pid_t waited;
    while ((waited = waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    if (waited < 0) fail(std::string("cannot wait for ffmpeg (") + std::strerror(errno) + ")");
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
    const std::string how = WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                              : "signal " + std::to_string(WTERMSIG(status));
    fail("ffmpeg failed (" + how + ")" + messages());
  }

 private:
  /// ffmpeg's messages, on one line: ": <line>; <line>" (at most 600 characters), or "".
  std::string messages() const {
    std::ifstream in(log_);
    std::string line, all;
    while (std::getline(in, line)) {
      while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
      if (!line.empty()) all += (all.empty() ? "" : "; ") + line;
    }
    if (all.size() > 600) all = "…" + all.substr(all.size() - 600);
    return all.empty() ? "" : ": " + all;
  }

  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error(movie_.string() + ": " + what); }

  fs::path movie_, log_;
  pid_t pid_ = -1;
  int in_ = -1;
};

/// Every recorded frame's picture meshes, in order: `visit(k, meshes)`.
template <class Visit> void for_each_picture(const Scene& scene, const FrameRecording& frames, Visit&& visit) {
  frames.for_each([&](int k, const Eigen::Matrix3Xf& x) {
    visit(k, scene_picture(scene, x.cast<double>(), frames.times()[static_cast<std::size_t>(k)]));
  });
}

}  // namespace

void write_movie(const fs::path& path, const Scene& scene, const FrameRecording& frames, double frame_rate,
                 const RenderOptions& picture) {
  if (!(std::isfinite(frame_rate) && frame_rate > 0))
    throw std::invalid_argument("write_movie: the frame rate must be finite and > 0");
  const fs::path ffmpeg = find_ffmpeg();
  if (ffmpeg.empty()) throw std::runtime_error(path.string() + ": " + ffmpeg_missing());
  if (frames.size() == 0) throw std::runtime_error(path.string() + ": no frame recorded");
  if (path.has_parent_path()) ensure_directory(path.parent_path().string());

  // One camera for the whole run: the bounding box of every frame, then every projection.
  ViewFit fit(picture);
  for_each_picture(scene, frames, [&](int, const std::vector<RenderMesh>& meshes) {
    for (const RenderMesh& m : meshes) fit.include(m.positions);
  });
  for_each_picture(scene, frames, [&](int, const std::vector<RenderMesh>& meshes) {
    for (const RenderMesh& m : meshes) fit.cover(m.positions);
  });
  const RenderView view = fit.view();

  fs::path log = path;
  log += ".ffmpeg-log";
  Encoder encoder(ffmpeg, path, log, picture, frame_rate);
  bool open = true;
  for_each_picture(scene, frames, [&](int, const std::vector<RenderMesh>& meshes) {
    if (open) open = encoder.write(render_rgb(meshes, picture, view));
  });
  encoder.finish();
  if (!open) throw std::runtime_error(path.string() + ": ffmpeg stopped reading the frames");
}

}  // namespace pce::sim
