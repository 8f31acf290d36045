#pragma once
/// \file
/// Integer handles into the mesh's element arrays (struct-of-arrays, slots reused through free
/// lists). A handle is a typed index; it does not keep its element alive.
///
/// Checked handles. When RGBMESH_CHECKED_HANDLES is 1 (by default in builds with assertions,
/// i.e. without NDEBUG; the rgbmesh::core CMake target sets it for its consumers: 1 in Debug,
/// 0 otherwise), a handle also carries the generation of its slot: the mesh counts, per slot,
/// how often an element in it was freed, and stamps that count into every handle it hands out.
/// A handle whose slot was freed since (and maybe reused by another element) is then "stale",
/// and the mesh reports its use instead of reading another element's data (see RgbMesh,
/// "Handles and their lifetime"). A handle made from a bare index (`VertexHandle(i)`) has
/// generation 0, "unknown", and is checked for range and liveness only. With the value 0 the
/// handle is the bare index: no field, no check, no cost. Every translation unit of a program
/// must see the same value (the CMake target takes care of that).
///
/// Equality, ordering and hashing use the index only: two handles of one slot compare equal
/// whatever their generations.

#include <cstdint>
#include <functional>

#ifndef RGBMESH_CHECKED_HANDLES
#ifdef NDEBUG
#define RGBMESH_CHECKED_HANDLES 0
#else
#define RGBMESH_CHECKED_HANDLES 1
#endif
#endif

namespace rgbmesh {

template <class Tag>
struct Handle {
  std::int32_t idx = -1;
#if RGBMESH_CHECKED_HANDLES
  /// The slot's generation when the mesh made this handle; 0: unknown (made from an index).
  std::uint32_t generation = 0;
#endif

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

#if !RGBMESH_CHECKED_HANDLES
/// Release builds pay nothing for the checks: a handle is its index.
static_assert(sizeof(VertexHandle) == sizeof(std::int32_t), "an unchecked handle is a bare index");
#endif

}  // namespace rgbmesh

template <class Tag>
struct std::hash<rgbmesh::Handle<Tag>> {
  std::size_t operator()(rgbmesh::Handle<Tag> h) const noexcept {
    return std::hash<std::int32_t>()(h.idx);
  }
};
