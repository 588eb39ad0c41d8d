// Versioned binary state of a Tracker (patches.####.bin). Little-endian,
// fixed-width fields; doubles are stored bit-exactly so a reloaded state
// continues exactly as the original would have.
//
// Layout (version 11; version 10 had no orientation settings, version 9 had no gap-fill and sink settings
// and no per-patch sunk log-area, version 8 had no birth-gap setting, version 7 no
// projection-slack setting, version 6 no
// birth-margin setting, version 5 no
// distorted setting and no per-patch texture offset, recovery or last recut
// frame, version 4 no kill-frames setting and no per-patch count of frames
// too close, version 3 no relax-frames setting): the magic, the version, a
// checksum of the raw streams (farmhash; damage anywhere is refused, not
// loaded), then three streams, each
// compressed with Blosc (byte shuffle + zstd) in chunks: the 8-byte fields
// (doubles, 64-bit counts), the 4-byte ones (ints, floats) and the bytes.
// Fields go to their stream in serialisation order, so the reader consumes
// each stream in the writer's order. Grouping fields by width lets the
// shuffle put the like bytes of neighbouring values together (the high bytes
// of coordinates barely change), which is where the compression comes from.
// Patch positions are not stored: they are their projections' positions.
#include <OpenImageIO/hash.h>
#include <blosc.h>

#include <array>
#include <cmath>
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
constexpr std::uint32_t kVersion = 11;
constexpr std::size_t kStreams = 3;  // 8-, 4- and 1-byte fields
static_assert(std::tuple_size_v<decltype(Tracker::UnpackedState::streams)> == kStreams);
constexpr std::size_t kTypeSize[kStreams] = {8, 4, 1};
constexpr std::size_t kChunk = std::size_t{1} << 26;  // 64 MiB of raw bytes per Blosc buffer
// Blosc's level 1 (zstd level 1): 2.5× faster than level 5 on blender-obstacle
// for 2 % larger states (docs/farm.md). The level is not in the format: any
// level reads back.
constexpr int kBloscLevel = 1;

/// The stream of a field type: by its alignment (an array of ints goes with
/// the ints).
template <class T>
constexpr std::size_t stream_of() {
  return alignof(T) >= 8 ? 0 : alignof(T) == 4 ? 1 : 2;
}

void append_raw(std::string& out, const void* data, std::size_t n) { out.append(static_cast<const char*>(data), n); }

std::uint64_t checksum(const std::array<std::string, kStreams>& streams) {
  std::uint64_t h = 0;
  for (const std::string& s : streams) h = OIIO::farmhash::Hash64WithSeed(s.data(), s.size(), h);
  return h;
}

/// The streams compressed: per stream its raw size, then chunks of
/// (compressed size, Blosc buffer).
std::string pack_streams(const std::array<std::string, kStreams>& streams) {
  std::string out;
  for (char c : kMagic) out += c;
  append_raw(out, &kVersion, sizeof kVersion);
  const std::uint64_t sum = checksum(streams);
  append_raw(out, &sum, sizeof sum);
  for (std::size_t s = 0; s < kStreams; ++s) {
    const std::string& raw = streams[s];
    const std::uint64_t size = raw.size();
    append_raw(out, &size, sizeof size);
    std::string buffer;
    for (std::size_t at = 0; at < raw.size(); at += kChunk) {
      const std::size_t n = std::min(kChunk, raw.size() - at);
      buffer.resize(n + BLOSC_MAX_OVERHEAD);
      const int written = blosc_compress_ctx(kBloscLevel, BLOSC_SHUFFLE, kTypeSize[s], n, raw.data() + at,
                                             buffer.data(), buffer.size(), "zstd", 0, 1);
      if (written <= 0) throw InternalError("state file: compression failed (" + std::to_string(written) + ")");
      const std::uint64_t packed = static_cast<std::uint64_t>(written);
      append_raw(out, &packed, sizeof packed);
      out.append(buffer.data(), static_cast<std::size_t>(written));
    }
  }
  return out;
}

/// The streams of a state file's bytes; InputError naming `path` for a file
/// that is not a state of this version or is damaged.
std::array<std::string, kStreams> unpack_streams(const std::string& bytes, const std::string& path) {
  std::size_t pos = 0;
  const auto take = [&](void* dst, std::size_t n) {
    if (pos + n > bytes.size()) throw InputError(path, "truncated state file");
    std::memcpy(dst, bytes.data() + pos, n);
    pos += n;
  };
  char magic[8];
  take(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) throw InputError(path, "not a fluidtex state file");
  std::uint32_t version;
  take(&version, sizeof version);
  if (version != kVersion) {
    throw InputError(path, "state file version " + std::to_string(version) + " (this build reads version " +
                               std::to_string(kVersion) + ")");
  }
  std::uint64_t sum;
  take(&sum, sizeof sum);
  std::array<std::string, kStreams> streams;
  for (std::string& raw : streams) {
    std::uint64_t size;
    take(&size, sizeof size);
    // Grown chunk by chunk, each validated first: a damaged size cannot
    // make the reader allocate what the file does not hold.
    for (std::uint64_t at = 0; at < size; at += kChunk) {
      const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, size - at));
      std::uint64_t packed;
      take(&packed, sizeof packed);
      if (packed > bytes.size() - pos) throw InputError(path, "truncated state file");
      std::size_t expected = 0;
      if (blosc_cbuffer_validate(bytes.data() + pos, packed, &expected) != 0 || expected != n) {
        throw InputError(path, "corrupt state file (compressed data)");
      }
      raw.resize(raw.size() + n);
      if (blosc_decompress_ctx(bytes.data() + pos, raw.data() + at, n, 1) != static_cast<int>(n)) {
        throw InputError(path, "corrupt state file (compressed data)");
      }
      pos += packed;
    }
  }
  if (pos != bytes.size()) throw InputError(path, "corrupt state file (trailing bytes)");
  if (checksum(streams) != sum) throw InputError(path, "corrupt state file (checksum)");
  return streams;
}

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    append_raw(streams_[stream_of<T>()], &v, sizeof(T));
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
  const std::array<std::string, kStreams>& streams() const { return streams_; }

 private:
  std::array<std::string, kStreams> streams_;
};

class Reader {
 public:
  Reader(const std::string& bytes, std::string path) : buf_(unpack_streams(bytes, path)), path_(std::move(path)) {}
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::string& buf = buf_[stream_of<T>()];
    std::size_t& pos = pos_[stream_of<T>()];
    if (pos + sizeof(T) > buf.size()) throw InputError(path_, "truncated state file");
    std::memcpy(&v, buf.data() + pos, sizeof(T));
    pos += sizeof(T);
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
    // Every element takes at least one byte of some stream.
    std::size_t left = 0;
    for (std::size_t s = 0; s < kStreams; ++s) left += buf_[s].size() - pos_[s];
    if (n > left) throw InputError(path_, "corrupt state file (bad array size)");
    v.resize(n);
    for (T& x : v) get(x);
  }
  bool done() const {
    for (std::size_t s = 0; s < kStreams; ++s) {
      if (pos_[s] != buf_[s].size()) return false;
    }
    return true;
  }
  const std::string& path() const { return path_; }

 private:
  std::array<std::string, kStreams> buf_;
  std::array<std::size_t, kStreams> pos_{};
  std::string path_;
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
  TrackingOptions::for_each_option(s.tracking, [&](const OptionInfo&, const auto& field) { put_option(w, field); });
  w.put(static_cast<std::uint8_t>(s.advection)), w.put(s.seed), w.put(s.candidates_per_disk);
  w.put(s.min_component_area);
  w.put(static_cast<std::uint8_t>(s.coverage_aware));
  w.put(s.patch_edge);
  w.put(static_cast<std::uint8_t>(s.motion));
}

void get_settings(Reader& r, TrackerSettings& s) {
  TrackingOptions::for_each_option(s.tracking, [&](const OptionInfo&, auto& field) { get_option(r, field); });
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

std::string Tracker::serialize() const { return pack_state(unpacked_state()); }

std::string Tracker::pack_state(const UnpackedState& state) { return pack_streams(state.streams); }

Tracker::UnpackedState Tracker::unpacked_state() const {
  Writer w;
  put_settings(w, settings_);
  w.put(static_cast<std::int32_t>(frame_));
  w.put(next_id_);
  w.put(mesh_ ? mesh_fingerprint(*mesh_) : std::uint64_t{0});
  w.put(static_cast<std::uint64_t>(patches_.size()));
  for (const Patch& p : patches_) {
    w.put(p.id), w.put(static_cast<std::uint8_t>(p.state)), w.put(p.kt);
    w.put(static_cast<std::int32_t>(p.created_frame)), w.put(static_cast<std::int32_t>(p.flagged_frame));
    w.put(static_cast<std::int32_t>(p.density)), w.put(static_cast<std::uint8_t>(p.cause));
    w.put(static_cast<std::int32_t>(p.close_frames)), w.put(static_cast<std::int32_t>(p.recut_frame));
    w.put(p.sunk);
    w.put(p.centre.point), w.put(p.centre.normal), w.put(p.anchor), w.put(p.texture_offset);
    w.put_vector(p.projections), w.put_vector(p.uvs), w.put_vector(p.triangles);
    w.put_vector(p.rest), w.put_vector(p.border), w.put_vector(p.quality), w.put_vector(p.weight);
    w.put_vector(p.recovery);
    w.put(p.max_distortion), w.put(p.disk_weight), w.put(p.motion);
  }
  w.put(static_cast<std::uint64_t>(retired_.size()));
  for (const RetiredPatch& r : retired_)
    w.put(r.id), w.put(static_cast<std::uint8_t>(r.cause)), w.put(static_cast<std::int32_t>(r.age));
  return {w.streams()};
}

namespace {

/// One patch of a state file, checked against itself and the frame's `mesh`
/// (InputError naming `path` for a corrupt one).
void read_patch(Reader& r, Patch& p, const FrameMesh& mesh, const std::string& path) {
  std::uint8_t state, cause;
  std::int32_t created, flagged, density, close_frames, recut;
  r.get(p.id), r.get(state), r.get(p.kt), r.get(created), r.get(flagged), r.get(density), r.get(cause);
  r.get(close_frames), r.get(recut);
  r.get(p.sunk);
  const bool known = enum_from_raw(state, p.state) && enum_from_raw(cause, p.cause);
  p.created_frame = created, p.flagged_frame = flagged, p.density = density, p.close_frames = close_frames;
  p.recut_frame = recut;
  r.get(p.centre.point), r.get(p.centre.normal), r.get(p.anchor), r.get(p.texture_offset);
  r.get_vector(p.projections), r.get_vector(p.uvs), r.get_vector(p.triangles);
  r.get_vector(p.rest), r.get_vector(p.border), r.get_vector(p.quality), r.get_vector(p.weight);
  r.get_vector(p.recovery);
  r.get(p.max_distortion), r.get(p.disk_weight), r.get(p.motion);
  const std::size_t nv = p.projections.size();
  p.positions.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) p.positions[v] = p.projections[v].position;
  bool ok = p.uvs.size() == nv && p.border.size() == nv && p.quality.size() == nv && p.weight.size() == nv &&
            (p.recovery.empty() || p.recovery.size() == nv) && p.rest.size() == p.triangles.size() &&
            close_frames >= 0 && std::isfinite(p.sunk) && known;
  for (const Tri& tri : p.triangles) {
    for (int v : tri) ok = ok && v >= 0 && static_cast<std::size_t>(v) < nv;
  }
  for (const SurfacePoint& s : p.projections)
    ok = ok && s.face >= 0 && static_cast<std::size_t>(s.face) < mesh.triangles.size();
  if (!ok) throw InputError(path, "corrupt state file (patch " + std::to_string(p.id) + ")");
}

}  // namespace

Tracker Tracker::load(const std::string& path, std::shared_ptr<const FrameMesh> mesh, std::optional<int> frame) {
  require_regular_file(path, "state file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open state file");
  std::ostringstream ss;
  ss << in.rdbuf();
  Reader r(ss.str(), path);
  TrackerSettings settings;
  get_settings(r, settings);
  Tracker t(settings);
  std::int32_t stored;
  std::uint64_t fingerprint, count;
  r.get(stored), r.get(t.next_id_), r.get(fingerprint), r.get(count);
  if (frame && stored != *frame) {
    throw InputError(path, "the state of frame " + std::to_string(stored) + ", not of frame " + std::to_string(*frame) +
                               " (a state file copied from another frame?)");
  }
  if (fingerprint != mesh_fingerprint(*mesh)) {
    throw InputError(path, "the state does not match frame " + std::to_string(stored) + "'s mesh (input changed?)");
  }
  t.patches_.resize(count);
  for (Patch& p : t.patches_) read_patch(r, p, *mesh, path);
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
  t.frame_ = stored;
  t.started_ = true;
  t.surface_ =
      std::shared_ptr<const SurfaceIndex>(new SurfaceIndex(*mesh), [mesh](const SurfaceIndex* s) { delete s; });
  t.mesh_ = std::move(mesh);
  return t;
}

}  // namespace fluidtex
