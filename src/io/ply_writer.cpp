#include "fluidtex/io/ply_writer.h"

#include <bit>

#include "fluidtex/util/atomic_file.h"
#include "fluidtex/util/error.h"

namespace fluidtex {

namespace {

void put_u32_le(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xffu);
}

}  // namespace

PlyWriter::PlyWriter(const std::vector<std::string>& comments, const std::vector<Property>& properties,
                     std::size_t vertices, std::size_t triangles)
    : properties_(properties), vertices_(vertices), triangles_(triangles) {
  bytes_ = "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& c : comments) bytes_ += "comment " + c + "\n";
  bytes_ += "element vertex " + std::to_string(vertices) + "\n";
  for (const Property& p : properties) {
    bytes_ += std::string("property ") + (p.type == Type::Float ? "float " : "uchar ") + p.name + "\n";
  }
  bytes_ += "element face " + std::to_string(triangles) + "\n";
  bytes_ += "property list uchar int vertex_indices\nend_header\n";
  std::size_t vertex_size = 0;
  for (const Property& p : properties) vertex_size += p.type == Type::Float ? 4 : 1;
  bytes_.reserve(bytes_.size() + vertices * vertex_size + triangles * 13);
}

void PlyWriter::put_value(Type type, double value) {
  if (properties_.empty() || faces_ > 0 || values_ >= vertices_ * properties_.size() ||
      properties_[values_ % properties_.size()].type != type) {
    throw InternalError("PLY writer: a vertex value out of the header's order");
  }
  ++values_;
  if (type == Type::Float)
    put_u32_le(bytes_, std::bit_cast<std::uint32_t>(static_cast<float>(value)));
  else
    bytes_ += static_cast<char>(static_cast<std::uint8_t>(value));
}

void PlyWriter::put_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (faces_ >= triangles_) throw InternalError("PLY writer: more triangles than the header's");
  ++faces_;
  bytes_ += static_cast<char>(3);
  for (const std::uint32_t v : {a, b, c}) put_u32_le(bytes_, v);
}

void PlyWriter::write(const std::string& path) const {
  if (values_ != vertices_ * properties_.size() || faces_ != triangles_) {
    throw InternalError(path + ": PLY writer: " + std::to_string(values_) + " vertex values and " +
                        std::to_string(faces_) + " triangles for a header of " + std::to_string(vertices_) + " x " +
                        std::to_string(properties_.size()) + " and " + std::to_string(triangles_));
  }
  write_text_atomically(path, bytes_);
}

}  // namespace fluidtex
