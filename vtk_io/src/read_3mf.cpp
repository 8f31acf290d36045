// 3MF (the 3D Manufacturing Format of slicers and CAD tools), read with lib3mf: the triangles
// of every object in the build, with the build items' and components' transforms applied.

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <Model/COM/NMR_DLLInterfaces.h>

#include "parsers.hpp"

namespace rgbmesh::detail {
namespace {

using Affine = std::array<std::array<double, 4>, 3>;  // rows of a 3 x 4 matrix: x' = A x + t

Affine affine(const NMR::MODELTRANSFORM& m) {
  Affine a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) a[r][c] = m.m_fFields[r][c];
  return a;
}

// outer ∘ inner: inner applied first.
Affine compose(const Affine& outer, const Affine& inner) {
  Affine out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      double v = c == 3 ? outer[r][3] : 0;
      for (int k = 0; k < 3; ++k) v += outer[r][k] * inner[k][c];
      out[r][c] = v;
    }
  return out;
}

double determinant(const Affine& a) {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// Releases a lib3mf handle at the end of its scope.
struct Release {
  void operator()(NMR::PLib3MFBase* p) const {
    if (p != nullptr) NMR::lib3mf_release(p);
  }
};
using Handle = std::unique_ptr<NMR::PLib3MFBase, Release>;

const char* unit_name(DWORD unit) {
  switch (unit) {
    case NMR::MODELUNIT_MICROMETER: return "micrometres";
    case NMR::MODELUNIT_MILLIMETER: return "millimetres";
    case NMR::MODELUNIT_CENTIMETER: return "centimetres";
    case NMR::MODELUNIT_INCH: return "inches";
    case NMR::MODELUNIT_FOOT: return "feet";
    case NMR::MODELUNIT_METER: return "metres";
    default: return "an unknown unit";
  }
}

class Reader3mf {
 public:
  explicit Reader3mf(const std::string& path) : path_(path) {}

  PolygonSoup read(std::string_view bytes) {
    NMR::PLib3MFModel* model = nullptr;
    if (NMR::lib3mf_createmodel(&model) != LIB3MF_OK) throw ResourceError(path_ + ": lib3mf could not create a model");
    const Handle model_handle(model);
    NMR::PLib3MFModelReader* reader = nullptr;
    check(model, NMR::lib3mf_model_queryreader(model, "3mf", &reader), "cannot read 3MF");
    const Handle reader_handle(reader);
    // Not strict: what the specification forbids but a mesh check names better (triangles that
    // repeat a vertex, which exporters write) is read, with lib3mf's warnings as one note.
    check(reader, NMR::lib3mf_reader_setstrictmodeactive(reader, false), "cannot read 3MF");
    // lib3mf reads from a buffer it does not change (its interface is not const).
    std::vector<BYTE> copy(bytes.begin(), bytes.end());
    try {
      check(reader, NMR::lib3mf_reader_readfrombuffer(reader, copy.data(), copy.size()), "not a readable 3MF file");
    } catch (const InputError& e) {
      // lib3mf refuses a whole file for one bad element (a triangle that repeats a vertex, which
      // 3MF forbids and some exporters write): say what else would read the part.
      throw InputError(std::string(e.what()) + " (lib3mf refuses it; export the part as STL, OBJ or PLY instead)");
    }
    copy = {};
    warnings(reader);
    DWORD unit = 0;
    check(model, NMR::lib3mf_model_getunit(model, &unit), "no unit");
    NMR::PLib3MFModelBuildItemIterator* items = nullptr;
    check(model, NMR::lib3mf_model_getbuilditems(model, &items), "no build");
    const Handle items_handle(items);
    std::size_t build_items = 0;
    for (BOOL more = false; NMR::lib3mf_builditemiterator_movenext(items, &more) == LIB3MF_OK && more;) {
      NMR::PLib3MFModelBuildItem* item = nullptr;
      check(items, NMR::lib3mf_builditemiterator_getcurrent(items, &item), "a build item cannot be read");
      const Handle item_handle(item);
      NMR::PLib3MFModelObjectResource* object = nullptr;
      check(item, NMR::lib3mf_builditem_getobjectresource(item, &object), "a build item names no object");
      const Handle object_handle(object);
      NMR::MODELTRANSFORM transform{};
      check(item, NMR::lib3mf_builditem_getobjecttransform(item, &transform), "a build item's transform cannot be read");
      add_object(object, affine(transform), 0);
      ++build_items;
    }
    if (soup_.faces.empty())
      throw InputError(path_ + ": the 3MF file has no mesh in its build (" + std::to_string(build_items) +
                       " build items" + (skipped_ > 0 ? ", " + std::to_string(skipped_) + " support or other objects" : "") + ")");
    std::string note = "3MF: " + std::to_string(meshes_) + (meshes_ == 1 ? " mesh" : " meshes") + " of " +
                       std::to_string(build_items) + (build_items == 1 ? " build item" : " build items") +
                       ", transforms applied; coordinates in " + unit_name(unit) + " as the file has them";
    if (skipped_ > 0) note += "; " + std::to_string(skipped_) + " support or other objects left out";
    if (mirrored_ > 0) note += "; " + std::to_string(mirrored_) + " mirrored by their transforms, turned back outwards";
    soup_.notes.push_back(note);
    return std::move(soup_);
  }

 private:
  void check(NMR::PLib3MFBase* from, LIB3MFRESULT result, const std::string& what) const {
    if (result == LIB3MF_OK) return;
    DWORD code = 0;
    LPCSTR message = nullptr;
    std::string detail;
    if (from != nullptr && NMR::lib3mf_getlasterror(from, &code, &message) == LIB3MF_OK && message != nullptr)
      detail = std::string(": ") + message;
    throw InputError(path_ + ": " + what + detail);
  }

  // lib3mf's warnings about the file: their count and the first, as one note.
  void warnings(NMR::PLib3MFModelReader* reader) {
    DWORD count = 0;
    if (NMR::lib3mf_reader_getwarningcount(reader, &count) != LIB3MF_OK || count == 0) return;
    DWORD code = 0;
    ULONG needed = 0;
    std::string first;
    if (NMR::lib3mf_reader_getwarningutf8(reader, 0, &code, nullptr, 0, &needed) == LIB3MF_OK && needed > 0) {
      std::vector<char> text(needed + 1, '\0');
      if (NMR::lib3mf_reader_getwarningutf8(reader, 0, &code, text.data(), needed + 1, &needed) == LIB3MF_OK)
        first = text.data();
    }
    soup_.notes.push_back("lib3mf read the file with " + std::to_string(count) + (count == 1 ? " warning" : " warnings") +
                          (first.empty() ? std::string() : " (the first: " + first + ")"));
  }

  // A mesh object's triangles, or a components object's parts, under `transform`.
  void add_object(NMR::PLib3MFModelObjectResource* object, const Affine& transform, int depth) {
    if (depth > 32) throw InputError(path_ + ": components nested more than 32 deep (a cycle?)");
    DWORD type = 0;
    check(object, NMR::lib3mf_object_gettype(object, &type), "an object's type cannot be read");
    BOOL is_mesh = false, is_components = false;
    check(object, NMR::lib3mf_object_ismeshobject(object, &is_mesh), "an object cannot be read");
    check(object, NMR::lib3mf_object_iscomponentsobject(object, &is_components), "an object cannot be read");
    if (type != NMR::MODELOBJECTTYPE_MODEL && type != NMR::MODELOBJECTTYPE_SOLIDSUPPORT &&
        type != NMR::MODELOBJECTTYPE_SURFACE && is_mesh) {
      ++skipped_;  // supports and "other" objects are not the part
      return;
    }
    if (is_components) {
      DWORD count = 0;
      check(object, NMR::lib3mf_componentsobject_getcomponentcount(object, &count), "a components object cannot be read");
      for (DWORD i = 0; i < count; ++i) {
        NMR::PLib3MFModelComponent* component = nullptr;
        check(object, NMR::lib3mf_componentsobject_getcomponent(object, i, &component), "a component cannot be read");
        const Handle component_handle(component);
        NMR::PLib3MFModelObjectResource* part = nullptr;
        check(component, NMR::lib3mf_component_getobjectresource(component, &part), "a component names no object");
        const Handle part_handle(part);
        NMR::MODELTRANSFORM local{};
        check(component, NMR::lib3mf_component_gettransform(component, &local), "a component's transform cannot be read");
        add_object(part, compose(transform, affine(local)), depth + 1);
      }
      return;
    }
    if (!is_mesh) return;
    DWORD vertices = 0, triangles = 0;
    check(object, NMR::lib3mf_meshobject_getvertexcount(object, &vertices), "a mesh cannot be read");
    check(object, NMR::lib3mf_meshobject_gettrianglecount(object, &triangles), "a mesh cannot be read");
    std::vector<NMR::MODELMESHVERTEX> points(vertices);
    std::vector<NMR::MODELMESHTRIANGLE> corners(triangles);
    if (vertices > 0)
      check(object, NMR::lib3mf_meshobject_getvertices(object, points.data(), vertices, nullptr), "a mesh's vertices cannot be read");
    if (triangles > 0)
      check(object, NMR::lib3mf_meshobject_gettriangleindices(object, corners.data(), triangles, nullptr),
            "a mesh's triangles cannot be read");
    const std::int64_t first = static_cast<std::int64_t>(soup_.points.size());
    for (const NMR::MODELMESHVERTEX& v : points) {
      double p[3];
      for (int r = 0; r < 3; ++r)
        p[r] = transform[r][0] * v.m_fPosition[0] + transform[r][1] * v.m_fPosition[1] +
               transform[r][2] * v.m_fPosition[2] + transform[r][3];
      soup_.points.emplace_back(p[0], p[1], p[2]);
    }
    // A transform that mirrors turns the triangles inside out: their order is turned back.
    const bool mirror = determinant(transform) < 0;
    mirrored_ += mirror;
    for (const NMR::MODELMESHTRIANGLE& t : corners) {
      std::vector<std::int64_t> face = {first + t.m_nIndices[0], first + t.m_nIndices[1], first + t.m_nIndices[2]};
      if (mirror) std::swap(face[1], face[2]);
      soup_.faces.push_back(std::move(face));
    }
    ++meshes_;
  }

  const std::string& path_;
  PolygonSoup soup_;
  std::size_t meshes_ = 0, skipped_ = 0, mirrored_ = 0;
};

}  // namespace

PolygonSoup parse_3mf(std::string_view data, const std::string& path) { return Reader3mf(path).read(data); }

}  // namespace rgbmesh::detail
