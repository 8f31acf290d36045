#pragma once
// Small helpers shared by the reading and writing halves of vtk_io.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::detail {

inline constexpr const char* input_extensions[] = {".3mf", ".obj", ".off", ".ply", ".stl", ".vtk", ".vtp", ".vtu"};
inline constexpr const char* point_cloud_extensions[] = {".3mf", ".obj", ".off", ".ply", ".pwn", ".stl",
                                                         ".vtk", ".vtp", ".vtu", ".xyz"};
inline constexpr const char* output_extensions[] = {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"};

// ".obj, .off, ..."
inline std::string joined(const char* const* begin, const char* const* end) {
  std::string text;
  for (auto it = begin; it != end; ++it) text += (it == begin ? "" : ", ") + std::string(*it);
  return text;
}

inline std::string lowercase_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

inline bool host_is_big_endian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

// `e` again with the file's path in front, keeping its kind: a defect of the mesh stays one, so
// that the caller can say how to repair it.
[[noreturn]] inline void rethrow_for_file(const std::filesystem::path& path, const InputError& e) {
  const std::string message = path.string() + ": " + e.what();
  if (const auto* defect = dynamic_cast<const MeshDefectError*>(&e))
    throw MeshDefectError(message, defect->hint());
  throw InputError(message);
}

// Shortest text that reads back as the same double.
inline std::string shortest(double x) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, result.ptr);
}

// Shortest text that reads back as the same float (sharpness: 2.8, not 2.7999999523162842).
inline std::string shortest(float x) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, result.ptr);
}

}  // namespace rgbmesh::detail
