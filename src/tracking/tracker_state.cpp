// Versioned binary state of a Tracker (patches.####.bin). Little-endian,
// fixed-width fields; doubles are stored bit-exactly so a reloaded state
// continues exactly as the original would have.
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <type_traits>

#include "fluidtex/tracking/tracker.h"
#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"
#include "fluidtex/util/random.h"

namespace fluidtex {

namespace {

constexpr char kMagic[8] = {'F', 'T', 'X', 'S', 'T', 'A', 'T', 'E'};
constexpr std::uint32_t kVersion = 2;

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    buf_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put(const Vec3& v) { put(v.x()), put(v.y()), put(v.z()); }
  void put(const Vec2& v) { put(v.x()), put(v.y()); }
  void put(const RestTriangle& t) { put(t[0]), put(t[1]), put(t[2]); }
  void put(const SurfacePoint& s) {
    put(static_cast<std::int32_t>(s.face)), put(s.bary), put(s.position), put(s.distance);
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    for (const T& x : v) put(x);
  }
  const std::string& bytes() const { return buf_; }

 private:
  std::string buf_;
};

class Reader {
 public:
  Reader(std::string bytes, std::string path) : buf_(std::move(bytes)), path_(std::move(path)) {}
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (pos_ + sizeof(T) > buf_.size()) throw InputError(path_, "truncated state file");
    std::memcpy(&v, buf_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
  }
  void get(Vec3& v) { get(v.x()), get(v.y()), get(v.z()); }
  void get(Vec2& v) { get(v.x()), get(v.y()); }
  void get(RestTriangle& t) { get(t[0]), get(t[1]), get(t[2]); }
  void get(SurfacePoint& s) {
    std::int32_t f;
    get(f);
    s.face = f;
    get(s.bary), get(s.position), get(s.distance);
  }
  template <class T>
  void get_vector(std::vector<T>& v) {
    std::uint64_t n;
    get(n);
    if (n > (buf_.size() - pos_)) throw InputError(path_, "corrupt state file (bad array size)");
    v.resize(n);
    for (T& x : v) get(x);
  }
  bool done() const { return pos_ == buf_.size(); }
  const std::string& path() const { return path_; }

 private:
  std::string buf_;
  std::string path_;
  std::size_t pos_ = 0;
};

// The tracking options in the order TrackingOptions::for_each_option lists
// them: lengths as doubles (resolved), counts as int32, enums as one byte.
void put_option(Writer& w, double v) { w.put(v); }
void put_option(Writer& w, int v) { w.put(static_cast<std::int32_t>(v)); }
void put_option(Writer& w, const std::optional<double>& v) {
  if (!v) throw InternalError("state file: tracking lengths must be resolved before saving");
  w.put(*v);
}
template <class E>
void put_option(Writer& w, E v) {
  static_assert(std::is_enum_v<E>);
  w.put(static_cast<std::uint8_t>(v));
}

void get_option(Reader& r, double& v) { r.get(v); }
void get_option(Reader& r, int& v) {
  std::int32_t raw;
  r.get(raw);
  v = raw;
}
void get_option(Reader& r, std::optional<double>& v) {
  double raw;
  r.get(raw);
  v = raw;
}
template <class E>
void get_option(Reader& r, E& v) {
  std::uint8_t raw;
  r.get(raw);
  if (!enum_from_raw(raw, v)) throw InputError(r.path(), "corrupt state file (settings)");
}

void put_settings(Writer& w, const TrackerSettings& s) {
  TrackingOptions::for_each_option(s.method, [&](const OptionInfo&, const auto& field) { put_option(w, field); });
  w.put(static_cast<std::uint8_t>(s.advection)), w.put(s.seed), w.put(s.candidates_per_disk);
  w.put(s.min_component_area);
  w.put(static_cast<std::uint8_t>(s.coverage_aware));
  w.put(s.patch_edge);
  w.put(static_cast<std::uint8_t>(s.motion));
}

void get_settings(Reader& r, TrackerSettings& s) {
  TrackingOptions::for_each_option(s.method, [&](const OptionInfo&, auto& field) { get_option(r, field); });
  get_option(r, s.advection);
  r.get(s.seed), r.get(s.candidates_per_disk);
  r.get(s.min_component_area);
  std::uint8_t coverage_aware;
  r.get(coverage_aware);
  s.coverage_aware = coverage_aware != 0;
  r.get(s.patch_edge);
  get_option(r, s.motion);
}

}  // namespace

std::uint64_t mesh_fingerprint(const FrameMesh& mesh) {
  std::uint64_t h = hash_values({mesh.positions.size(), mesh.triangles.size()});
  auto mix_double = [&](double d) {
    std::uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    h = mix64(h ^ bits);
  };
  for (const Vec3& p : mesh.positions) mix_double(p.x()), mix_double(p.y()), mix_double(p.z());
  for (const Vec3& v : mesh.velocities) mix_double(v.x()), mix_double(v.y()), mix_double(v.z());
  for (const Tri& t : mesh.triangles)
    h = mix64(h ^ hash_values({static_cast<std::uint64_t>(t[0]), static_cast<std::uint64_t>(t[1]),
                               static_cast<std::uint64_t>(t[2])}));
  return h;
}

void Tracker::save(const std::string& path) const { write_text_atomically(path, serialize()); }

std::string Tracker::serialize() const {
  Writer w;
  for (char c : kMagic) w.put(c);
  w.put(kVersion);
  put_settings(w, settings_);
  w.put(static_cast<std::int32_t>(frame_));
  w.put(next_id_);
  w.put(mesh_ ? mesh_fingerprint(*mesh_) : std::uint64_t{0});
  w.put(static_cast<std::uint64_t>(patches_.size()));
  for (const Patch& p : patches_) {
    w.put(p.id), w.put(static_cast<std::uint8_t>(p.state)), w.put(p.kt);
    w.put(static_cast<std::int32_t>(p.created_frame)), w.put(static_cast<std::int32_t>(p.flagged_frame));
    w.put(static_cast<std::int32_t>(p.density)), w.put(static_cast<std::uint8_t>(p.cause));
    w.put(p.center.point), w.put(p.center.normal), w.put(p.anchor);
    w.put_vector(p.positions), w.put_vector(p.projections), w.put_vector(p.uvs), w.put_vector(p.triangles);
    w.put_vector(p.rest), w.put_vector(p.border), w.put_vector(p.quality), w.put_vector(p.weight);
    w.put(p.max_distortion), w.put(p.disk_weight), w.put(p.motion);
  }
  w.put(static_cast<std::uint64_t>(retired_.size()));
  for (const RetiredPatch& r : retired_)
    w.put(r.id), w.put(static_cast<std::uint8_t>(r.cause)), w.put(static_cast<std::int32_t>(r.age));
  return w.bytes();
}

Tracker Tracker::load(const std::string& path, std::shared_ptr<const FrameMesh> mesh) {
  require_regular_file(path, "state file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open state file");
  std::ostringstream ss;
  ss << in.rdbuf();
  Reader r(ss.str(), path);
  char magic[8];
  for (char& c : magic) r.get(c);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) throw InputError(path, "not a fluidtex state file");
  std::uint32_t version;
  r.get(version);
  if (version != kVersion) {
    throw InputError(path, "state file version " + std::to_string(version) + " (this build reads version " +
                               std::to_string(kVersion) + ")");
  }
  TrackerSettings settings;
  get_settings(r, settings);
  Tracker t(settings);
  std::int32_t frame;
  std::uint64_t fingerprint, count;
  r.get(frame), r.get(t.next_id_), r.get(fingerprint), r.get(count);
  if (fingerprint != mesh_fingerprint(*mesh)) {
    throw InputError(path, "the state does not match frame " + std::to_string(frame) + "'s mesh (input changed?)");
  }
  t.patches_.resize(count);
  for (Patch& p : t.patches_) {
    std::uint8_t state, cause;
    std::int32_t created, flagged, density;
    r.get(p.id), r.get(state), r.get(p.kt), r.get(created), r.get(flagged), r.get(density), r.get(cause);
    const bool known = enum_from_raw(state, p.state) && enum_from_raw(cause, p.cause);
    p.created_frame = created, p.flagged_frame = flagged, p.density = density;
    r.get(p.center.point), r.get(p.center.normal), r.get(p.anchor);
    r.get_vector(p.positions), r.get_vector(p.projections), r.get_vector(p.uvs), r.get_vector(p.triangles);
    r.get_vector(p.rest), r.get_vector(p.border), r.get_vector(p.quality), r.get_vector(p.weight);
    r.get(p.max_distortion), r.get(p.disk_weight), r.get(p.motion);
    const std::size_t nv = p.positions.size();
    bool ok = p.projections.size() == nv && p.uvs.size() == nv && p.border.size() == nv && p.quality.size() == nv &&
              p.weight.size() == nv && p.rest.size() == p.triangles.size() && known;
    for (const Tri& tri : p.triangles) {
      for (int v : tri) ok = ok && v >= 0 && static_cast<std::size_t>(v) < nv;
    }
    for (const SurfacePoint& s : p.projections)
      ok = ok && s.face >= 0 && static_cast<std::size_t>(s.face) < mesh->triangles.size();
    if (!ok) throw InputError(path, "corrupt state file (patch " + std::to_string(p.id) + ")");
  }
  std::uint64_t retired;
  r.get(retired);
  if (retired > t.next_id_) throw InputError(path, "corrupt state file (bad retired count)");
  t.retired_.resize(retired);
  for (RetiredPatch& x : t.retired_) {
    std::uint8_t cause;
    std::int32_t age;
    r.get(x.id), r.get(cause), r.get(age);
    if (!enum_from_raw(cause, x.cause) || x.cause == RetireCause::None || age < 0)
      throw InputError(path, "corrupt state file (retired patch)");
    x.age = age;
  }
  if (!r.done()) throw InputError(path, "corrupt state file (trailing bytes)");
  t.frame_ = frame;
  t.started_ = true;
  t.surface_ =
      std::shared_ptr<const SurfaceIndex>(new SurfaceIndex(*mesh), [mesh](const SurfaceIndex* s) { delete s; });
  t.mesh_ = std::move(mesh);
  return t;
}

}  // namespace fluidtex
