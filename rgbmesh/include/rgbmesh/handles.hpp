#pragma once
// Integer handles into the mesh's element arrays (struct-of-arrays, slots reused through free
// lists). A handle is a typed index; it does not keep its element alive.

#include <cstdint>
#include <functional>

namespace rgbmesh {

template <class Tag>
struct Handle {
  std::int32_t idx = -1;

  constexpr Handle() = default;
  constexpr explicit Handle(std::int32_t i) : idx(i) {}
  constexpr bool valid() const { return idx >= 0; }
  constexpr explicit operator bool() const { return valid(); }
  friend constexpr bool operator==(Handle a, Handle b) { return a.idx == b.idx; }
  friend constexpr bool operator!=(Handle a, Handle b) { return a.idx != b.idx; }
  friend constexpr bool operator<(Handle a, Handle b) { return a.idx < b.idx; }
};

using VertexHandle = Handle<struct VertexTag>;
using EdgeHandle = Handle<struct EdgeTag>;
using TriangleHandle = Handle<struct TriangleTag>;

}  // namespace rgbmesh

template <class Tag>
struct std::hash<rgbmesh::Handle<Tag>> {
  std::size_t operator()(rgbmesh::Handle<Tag> h) const noexcept {
    return std::hash<std::int32_t>()(h.idx);
  }
};
