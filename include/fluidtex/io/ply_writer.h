/// @file ply_writer.h
/// @brief The one PLY form fluidtex writes (UV meshes, example scenes, debug
/// views): binary little-endian, a vertex element of float and uchar
/// properties, then a face element of triangles
/// (`property list uchar int vertex_indices`). Identical data gives
/// identical bytes; the file is written atomically.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace fluidtex {

class PlyWriter {
 public:
  enum class Type : std::uint8_t { Float, UChar };
  struct Property {
    const char* name;
    Type type = Type::Float;
  };

  /// The header: `comment` lines in order, `vertices` vertices of
  /// `properties`, `triangles` faces. The values follow, vertex by vertex
  /// in property order (put), then the triangles (put_triangle).
  PlyWriter(const std::vector<std::string>& comments, const std::vector<Property>& properties, std::size_t vertices,
            std::size_t triangles);

  /// The next vertex value: a float property's value, as a 32-bit float.
  void put(double value) { put_value(Type::Float, value); }
  /// The next vertex value: a uchar property's.
  void put(std::uint8_t value) { put_value(Type::UChar, value); }
  void put_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);

  /// Writes the file atomically; InternalError when the values put do not
  /// fill the header's counts, or the file cannot be written.
  void write(const std::string& path) const;

 private:
  void put_value(Type type, double value);

  std::vector<Property> properties_;
  std::size_t vertices_, triangles_;
  std::size_t values_ = 0, faces_ = 0;
  std::string bytes_;
};

}  // namespace fluidtex
