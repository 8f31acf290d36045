// rgbmesh.read and Mesh.write: every format the tool reads and writes (vtk_io), the RGB state
// of .vtp/.vtu files included, written atomically.

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/vtk_io.hpp"
#if defined(RGBMESH_PYTHON_REPAIR)
#include "rgbmesh/repair/repair.hpp"
#endif

namespace py = pybind11;

namespace rgbmesh::python {

void bind_io(py::module_& m) {
  m.def(
      "read",
      [](const std::filesystem::path& path, bool triangulate, bool repair, const py::object& sharp_angle) {
        SoupOptions o;
        o.triangulate = triangulate;
        if (repair) {
#if defined(RGBMESH_PYTHON_REPAIR)
          o = repair::soup_options(triangulate, true);
#else
          throw InputError(
              "repair=True: this build has no rgbmesh::repair (RGBMESH_WITH_REPAIR, needs CGAL)");
#endif
        }
        if (!sharp_angle.is_none()) {
          o.sharp_angle = py::cast<double>(sharp_angle);
          if (!(o.sharp_angle > 0.0 && o.sharp_angle < 180.0)) throw InputError("sharp_angle: degrees in (0, 180)");
        }
        RgbMeshFile file;
        try {
          py::gil_scoped_release release;
          file = read_rgb_mesh(path, o);
        } catch (const MeshDefectError& e) {
          // What to try next, in the caller's terms.
          throw InputError(std::string(e.what()) + " (repair=True " + e.hint() + ")");
        }
        // With repair, the notes say what was changed: warnings, which the caller may silence or
        // turn into errors.
        if (repair)
          for (const std::string& note : file.notes)
            if (PyErr_WarnEx(PyExc_UserWarning, (path.string() + ": " + note).c_str(), 1) < 0)
              throw py::error_already_set();
        return std::move(file.mesh);
      },
      py::arg("path"), py::arg("triangulate") = false, py::arg("repair") = false, py::arg("sharp_angle") = py::none(),
      "Reads a mesh file (.3mf, .obj, .off, .ply, .stl, .vtk, .vtp, .vtu). A .vtp/.vtu that rgbmesh wrote comes "
      "back with its RGB state (levels, colours, every inserted vertex); any other file as a base mesh. "
      "triangulate: split polygons into triangles. repair: merge vertices at equal positions, collapse degenerate and "
      "needle triangles, split non-manifold edges and vertices, orient consistently (as the tool's --repair; "
      "not for a file with an RGB state; what was changed is said in UserWarnings). An OBJ file's crease and "
      "corner tags (OpenSubdiv's 't crease', 't corner', 't creasemethod') are read; sharp_angle: also every "
      "edge whose triangles' normals differ by more than this many degrees is a crease (Mesh.sharp_features). "
      "Bad files: ValueError naming the file and the line or element.");
  py::class_<RgbMesh>(m.attr("Mesh")).def(
      "write",
      [](RgbMesh& mesh, const std::filesystem::path& path, bool limit, const std::string& compression) {
        WriteOptions o;
        if (!compression_from_name(compression, o.compression))
          throw InputError("compression '" + compression + "': lz4, zlib or none");
        py::gil_scoped_release release;
        write_rgb_mesh(path, mesh, o, limit);
      },
      py::arg("path"), py::kw_only(), py::arg("limit") = false, py::arg("compression") = "lz4",
      "Writes the mesh (the format from the extension: .obj, .off, .ply, .stl, .vtp, .vtu), atomically; "
      ".vtp and .vtu carry the RGB state, which read() restores. limit: the vertices at their limit "
      "positions instead of their control points. An unwritable path: OSError.");
}

}  // namespace rgbmesh::python
