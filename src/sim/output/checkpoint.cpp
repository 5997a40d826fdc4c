// SPDX-License-Identifier: MIT
// Checkpoint files (pce/sim/checkpoint.hpp).
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/carried_state.hpp>
#include <pce/sim/effect.hpp>
#include <pce/sim/input_error.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <regex>
#include <stdexcept>

namespace pce::sim {

namespace {

constexpr char kMagic[8] = {'P', 'C', 'E', 'S', 'I', 'M', 'C', 'K'};
constexpr std::uint32_t kByteOrderMark = 0x01020304;

/// What `effect` carries from one step to the next (`CarriedState`), else nothing.
std::string state_of(const Effect& effect) {
  const auto* c = dynamic_cast<const CarriedState*>(&effect);
  return c ? c->save_state() : std::string();
}

/// Restores `state` (from state_of) into `effect`; throws std::invalid_argument when it does
/// not fit.
void restore_state(Effect& effect, const std::string& state) {
  if (auto* c = dynamic_cast<CarriedState*>(&effect))
    c->load_state(state);
  else if (!state.empty())
    throw std::invalid_argument(std::string(effect.name()) + ": unexpected saved state");
}

template <class T> void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/// Reads fixed-size values from the file's bytes; every read past the end throws.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  template <class T> T get() {
    T value;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  const char* take(std::size_t count) {
    if (count > bytes_.size() - at_) throw std::invalid_argument("truncated");
    const char* p = bytes_.data() + at_;
    at_ += count;
    return p;
  }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

template <class Derived> std::uint64_t hash_matrix(const Eigen::DenseBase<Derived>& m, std::uint64_t seed) {
  const auto& e = m.derived().eval();
  return fnv1a64(std::string_view(reinterpret_cast<const char*>(e.data()),
                                  static_cast<std::size_t>(e.size()) * sizeof(typename Derived::Scalar)),
                 seed);
}

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed) {
  std::uint64_t h = seed;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::uint64_t simulation_fingerprint(std::string_view scene, const Model& model) {
  std::uint64_t h = fnv1a64(scene);
  h = hash_matrix(model.rest, h);
  h = hash_matrix(model.triangles, h);
  h = hash_matrix(model.segments, h);
  h = hash_matrix(model.tetrahedra, h);  // nothing for a model without volumes
  return hash_matrix(model.mass, h);
}

std::string checkpoint_path(const std::string& dir, int frame) {
  char name[40];
  std::snprintf(name, sizeof name, "checkpoint_%04d.pcecp", frame);
  return (std::filesystem::path(dir) / name).string();
}

std::filesystem::path latest_checkpoint(const std::filesystem::path& dir) {
  static const std::regex name("checkpoint_([0-9]{4,9})\\.pcecp");
  std::filesystem::path best;
  long best_frame = -1;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    std::smatch m;
    const std::string file = entry.path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    const long frame = std::stol(m[1].str());
    if (frame > best_frame) best_frame = frame, best = entry.path();
  }
  return best;
}

void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, std::uint64_t fingerprint) {
  std::string out(kMagic, sizeof kMagic);
  put(out, kCheckpointFormatVersion);
  put(out, kByteOrderMark);
  put(out, fingerprint);
  put(out, static_cast<std::int32_t>(sim.frame));
  put(out, sim.time);
  put(out, static_cast<std::int64_t>(sim.x.cols()));
  out.append(reinterpret_cast<const char*>(sim.x.data()), static_cast<std::size_t>(sim.x.size()) * sizeof(double));
  out.append(reinterpret_cast<const char*>(sim.v.data()), static_cast<std::size_t>(sim.v.size()) * sizeof(double));
  put(out, static_cast<std::uint32_t>(sim.effects.size()));
  for (const auto& e : sim.effects) {
    const std::string name = e->name(), state = state_of(*e);
    put(out, static_cast<std::uint32_t>(name.size()));
    out += name;
    put(out, static_cast<std::uint64_t>(state.size()));
    out += state;
  }
  put(out, fnv1a64(out));
  std::filesystem::path temporary = path;
  temporary += ".partial";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file.write(out.data(), static_cast<std::streamsize>(out.size()));
    file.flush();
    if (!file) throw std::runtime_error(temporary.string() + ": cannot write the checkpoint");
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) throw std::runtime_error(path.string() + ": cannot write the checkpoint (" + error.message() + ")");
}

void read_checkpoint(const std::filesystem::path& path, Simulation& sim, std::uint64_t fingerprint) {
  const auto refuse = [&](const std::string& why) -> void { throw InputError(path.string(), "", why); };
  std::ifstream file(path, std::ios::binary);
  if (!file) refuse("cannot open the checkpoint");
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (bytes.size() < sizeof kMagic + 8 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    refuse("not a pce-sim checkpoint");
  Eigen::Matrix3Xd x, v;
  std::vector<std::string> states;
  std::int32_t frame = 0;
  double time = 0;
  try {
    Reader r(bytes);
    r.take(sizeof kMagic);
    const auto version = r.get<std::uint32_t>();
    if (version != kCheckpointFormatVersion)
      refuse("checkpoint format version " + std::to_string(version) + ", this pce-sim reads version " +
             std::to_string(kCheckpointFormatVersion));
    if (r.get<std::uint32_t>() != kByteOrderMark) refuse("written on a machine of another byte order");
    const std::size_t body = bytes.size() - sizeof(std::uint64_t);
    std::uint64_t checksum = 0;
    std::memcpy(&checksum, bytes.data() + body, sizeof checksum);
    if (checksum != fnv1a64(std::string_view(bytes.data(), body))) refuse("truncated or corrupted (checksum)");
    if (r.get<std::uint64_t>() != fingerprint)
      refuse(
          "written for another scene (the scene file, a mesh file or a physics option such as --hessian, "
          "--broad-phase, --single-solve, --mode, --iterations or --tolerance differs)");
    frame = r.get<std::int32_t>();
    time = r.get<double>();
    const auto n = r.get<std::int64_t>();
    if (frame < 0 || !std::isfinite(time) || n != sim.model.vertex_count())
      refuse("the frame, time or vertex count does not fit this scene");
    x.resize(3, n);
    v.resize(3, n);
    const std::size_t coordinates = static_cast<std::size_t>(3 * n) * sizeof(double);
    std::memcpy(x.data(), r.take(coordinates), coordinates);
    std::memcpy(v.data(), r.take(coordinates), coordinates);
    if (!x.allFinite() || !v.allFinite()) refuse("non-finite positions or velocities");
    const auto effects = r.get<std::uint32_t>();
    if (effects != sim.effects.size())
      refuse(std::to_string(effects) + " effects saved, the scene has " + std::to_string(sim.effects.size()));
    for (std::uint32_t k = 0; k < effects; ++k) {
      const auto name_size = r.get<std::uint32_t>();
      const std::string name(r.take(name_size), name_size);
      if (name != sim.effects[k]->name())
        refuse("effect " + std::to_string(k) + " is \"" + name + "\" in the checkpoint, \"" + sim.effects[k]->name() +
               "\" in the scene");
      const auto state_size = r.get<std::uint64_t>();
      states.emplace_back(r.take(state_size), state_size);
    }
  } catch (const std::invalid_argument&) {
    refuse("truncated");
  }
  // The effects take their states one by one; when one refuses its state, those restored
  // before it get their previous state back and the simulation is left unchanged.
  std::vector<std::string> previous;
  for (const auto& e : sim.effects) previous.push_back(state_of(*e));
  std::size_t k = 0;
  try {
    for (; k < sim.effects.size(); ++k) restore_state(*sim.effects[k], states[k]);
  } catch (const std::invalid_argument& error) {
    for (std::size_t j = 0; j < k; ++j) restore_state(*sim.effects[j], previous[j]);
    refuse(error.what());
  }
  sim.x = std::move(x);
  sim.v = std::move(v);
  sim.frame = frame;
  sim.time = time;
}

}  // namespace pce::sim
