// rgbmesh.fit: rgbmesh::fit from numpy — the base made from the target (decimated, or
// reconstructed from a point cloud) or given, the control points fitted with Ceres, the GIL
// released and Ctrl-C checked after every iteration.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fit/base.hpp"
#include "rgbmesh/fit/fit.hpp"
#include "rgbmesh/fit/fit_target.hpp"
#include "rgbmesh/mesh.hpp"
#if defined(RGBMESH_PYTHON_REPAIR)
#include "rgbmesh/repair/repair.hpp"
#endif
#include "rgbmesh/vtk_io.hpp"

namespace py = pybind11;

namespace rgbmesh::python {

namespace {

std::vector<Vec3> points_from(const py::handle& object, const char* what) {
  return points_of_array(py::cast<DoubleArray>(object), what);
}

std::vector<std::vector<std::int64_t>> faces_from(const py::handle& object, const char* what) {
  const IndexArray a = py::cast<IndexArray>(object);
  if (a.ndim() != 2 || a.shape(1) != 3) throw InputError(std::string(what) + ": an (m, 3) array is needed");
  std::vector<std::vector<std::int64_t>> f(static_cast<std::size_t>(a.shape(0)));
  for (std::size_t i = 0; i < f.size(); ++i) f[i].assign(a.data() + 3 * i, a.data() + 3 * i + 3);
  return f;
}

bool is_path(const py::handle& h) {
  return py::isinstance<py::str>(h) || py::hasattr(h, "__fspath__");
}

// The base mesh of a fit from what the user gave: a level-0 Mesh, (points, triangles) or a file.
fit::Base given_base(const py::object& base) {
  fit::Base b;
  b.source = fit::BaseSource::given;
  if (py::isinstance<RgbMesh>(base)) {
    const RgbMesh& mesh = base.cast<const RgbMesh&>();
    if (mesh.max_level() != 0)
      throw InputError("base: the mesh is refined (to level " + std::to_string(mesh.max_level()) +
                       "); a fit moves the control points of a base mesh (level 0): coarsen it with "
                       "refine(uniform=0), or give the refined mesh's arrays as a new base");
    const MeshSnapshot s = mesh.snapshot();
    b.mesh.points = s.points;
    b.mesh.triangles = s.triangles;
  } else if (is_path(base)) {
    const std::filesystem::path path = base.cast<std::filesystem::path>();
    b.mesh = read_mesh(path);
    for (const std::string& note : b.mesh.notes) b.notes.push_back(path.string() + ": " + note);
    b.mesh.notes.clear();
  } else if (py::isinstance<py::tuple>(base) && py::len(base) == 2) {
    const py::tuple t = base.cast<py::tuple>();
    const MeshSnapshot s = mesh_from_arrays(py::cast<DoubleArray>(t[0]), py::cast<IndexArray>(t[1]), "base").snapshot();
    b.mesh.points = s.points;
    b.mesh.triangles = s.triangles;
  } else {
    throw InputError("base: a Mesh (level 0), a (points, triangles) pair or a mesh file's path");
  }
  b.topology = fit::topology_of(b.mesh);
  return b;
}

fit::Loss loss_of(const std::string& name) {
  if (name == "huber") return fit::Loss::huber;
  if (name == "cauchy") return fit::Loss::cauchy;
  if (name == "none") return fit::Loss::none;
  throw InputError("loss: '" + name + "' is not one of huber, cauchy, none");
}

py::dict iteration_dict(const fit::IterationReport& it) {
  py::dict d;
  d["iteration"] = it.iteration;
  d["rms"] = it.rms;
  d["max"] = it.max;
  d["seconds"] = it.seconds;
  return d;
}

py::dict run_fit(const py::object& target, const py::object& triangles, const py::object& normals, const py::object& base,
                 std::size_t base_faces, int levels, const std::string& loss, double smooth, int iterations,
                 const py::object& callback, const std::string& reconstruction, bool ignore_faces, bool check,
                 bool repair) {
  fit::TargetFitOptions options;
  fit::FitOptions& o = options.fit;
  o.loss = loss_of(loss);
  if (levels < 1 || levels > 6) throw InputError("levels: must be in [1, 6], got " + std::to_string(levels));
  if (iterations < 1) throw InputError("iterations: must be at least 1");
  if (!(smooth >= 0)) throw InputError("smooth: must be >= 0");
  if (base.is_none() && base_faces < 4) throw InputError("base_faces: must be at least 4");
  o.levels = levels;
  o.smooth = smooth;
  o.max_iterations = iterations;
  if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
    throw InputError("callback: must be callable, callback(iteration)");

  // The target: a file (its points, faces and normals, as rgbmesh fit reads it) or arrays.
  PointCloud cloud;
  if (is_path(target)) {
    cloud = read_point_cloud(target.cast<std::filesystem::path>());
  } else {
    cloud.points = points_from(target, "target");
    if (!triangles.is_none()) cloud.faces = faces_from(triangles, "target_triangles");
    if (!normals.is_none()) {
      cloud.normals = points_from(normals, "normals");
      if (cloud.normals.size() != cloud.points.size())
        throw InputError("normals: one per target point is needed (" + std::to_string(cloud.points.size()) + ")");
    }
  }
  if (cloud.points.empty()) throw InputError("target: no points");

  options.base.faces = base_faces;
  options.base.ignore_faces = ignore_faces;
  if (repair) {
#if defined(RGBMESH_PYTHON_REPAIR)
    options.base.soup = repair::soup_options(false, true);
#else
    throw InputError("repair=True: this build has no rgbmesh::repair (RGBMESH_WITH_REPAIR, needs CGAL)");
#endif
  }
  if (!fit::reconstruction_method_from_name(reconstruction, options.base.reconstruction.method))
    throw InputError("reconstruction: '" + reconstruction + "' is not automatic, poisson or advancing-front");
  std::optional<fit::Base> given;
  if (!base.is_none()) given = given_base(base);
  fit::TargetFit f;
  {
    py::gil_scoped_release release;
    PolygonSoup soup;
    soup.points = cloud.points;
    soup.faces = cloud.faces;
    soup.numbered_vertices = cloud.numbered_vertices;
    fit::StageControl control;
    control.on_step = [](const std::string&, double) {
      py::gil_scoped_acquire gil;
      throw_if_interrupted();
    };
    try {
      f = fit::prepare_target_fit(soup, cloud.normals, given, options, control);
    } catch (const MeshDefectError& e) {
      throw InputError("target: " + std::string(e.what()) + " (repair=True " + e.hint() + ")");
    }
    fit::run_target_fit(
        f, options,
        [&](const fit::IterationReport& it) {
          py::gil_scoped_acquire gil;
          if (!callback.is_none()) callback(iteration_dict(it));
          throw_if_interrupted();
        },
        control);
  }
  if (check && !f.verdict.accepted)
    throw InputError(f.verdict.reason + " (check=False returns the fit anyway, with accepted = False)");
  const fit::Base& b = f.base;
  const fit::FitResult& r = f.result;
  py::dict out;
  out["mesh"] = RgbMesh::from_triangles(r.control_points, b.mesh.triangles, b.mesh.sharp);
  out["base"] = RgbMesh::from_triangles(b.mesh.points, b.mesh.triangles, b.mesh.sharp);
  out["base_source"] = fit::to_string(b.source);
  out["topology"] = fit::to_string(b.topology);
  out["rms"] = r.rms;
  out["max"] = r.max;
  out["diagonal"] = r.diagonal;
  out["seconds"] = r.seconds;
  out["smooth"] = r.smooth;
  py::list its;
  for (const auto& it : r.iterations) its.append(iteration_dict(it));
  out["iterations"] = its;
  out["accepted"] = f.verdict.accepted;
  out["reason"] = f.verdict.reason;
  out["surface_to_target_rms"] = f.distances.to_target_rms;
  out["surface_to_target_max"] = f.distances.to_target_max;
  out["surface_to_target"] = array_of<double>(f.distances.to_target.size(), 1, f.distances.to_target.data());
  out["target_is_surface"] = f.target_is_surface;
  out["targets"] = array_of<double>(f.targets.size(), 3, f.targets.empty() ? nullptr : &f.targets[0].x);
  py::list notes;
  for (const auto& n : cloud.notes) notes.append(n);
  for (const auto& n : f.target_notes) notes.append(n);
  for (const auto& n : f.notes) notes.append(n);
  out["notes"] = notes;
  out["distances"] = array_of<double>(r.distance.size(), 1, r.distance.data());
  const std::vector<Vec3> limit = r.stencils.evaluate(r.control_points);
  out["limit_points"] = array_of<double>(limit.size(), 3, limit.empty() ? nullptr : &limit[0].x);
  out["limit_triangles"] = array_of<std::int32_t>(r.stencils.triangles.size(), 3,
                                                  r.stencils.triangles.empty() ? nullptr : r.stencils.triangles[0].data());
  return out;
}

}  // namespace

void bind_fit(py::module_& m) {
  m.def("fit", &run_fit, py::arg("target"), py::kw_only(), py::arg("target_triangles") = py::none(),
        py::arg("normals") = py::none(), py::arg("base") = py::none(), py::arg("base_faces") = 1000,
        py::arg("levels") = 3, py::arg("loss") = "huber", py::arg("smooth") = 1e-3, py::arg("iterations") = 30,
        py::arg("callback") = py::none(), py::arg("reconstruction") = "automatic", py::arg("ignore_faces") = false,
        py::arg("check") = true, py::arg("repair") = false,
        "Fits a Loop subdivision surface to target points (an (n, 3) array, with optional target_triangles and "
        "normals, or a file rgbmesh fit reads), as rgbmesh fit does: the base is `base` (a level-0 Mesh, "
        "(points, triangles) or a file) or made from the target (its faces decimated to about base_faces "
        "triangles, or a surface reconstructed from a point cloud); its control points move so that the limit "
        "surface at `levels` passes through the targets. callback(iteration) after every iteration. Returns a "
        "dict: mesh (the fitted base), base (the starting one), rms, max, diagonal, iterations, notes, distances "
        "(per target, to the surface), targets (the points fitted: a mesh target's vertices and points on its "
        "triangles), surface_to_target (per limit point) with its rms and max, accepted and reason (the "
        "two-sided check; with check=True, the default, a rejected fit raises ValueError), limit_points and "
        "limit_triangles (the fitted limit surface), base_source, topology, smooth, seconds. reconstruction: "
        "automatic, poisson or advancing-front; ignore_faces: fit a mesh target's vertices as a point cloud; repair: repair the target's faces first (as "
        "rgbmesh.read(repair=True)).");
}

}  // namespace rgbmesh::python
