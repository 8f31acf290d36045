#pragma once
// What the CLI tests read from an adapt run: the report's cycles, and a cycle file's triangles
// by their corners' positions (to compare meshes without their numbering).

#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <vtkIdList.h>

#include "../apps/json_read.hpp"
#include "cli_fixture.hpp"

namespace rgbmesh::testing {

using rgbmesh::cli::JsonReader;
using rgbmesh::cli::JsonValue;

struct Cycle {
  long dofs = 0, triangles = 0, removals = 0;
  double estimate = 0, error_l2 = 0, error_h1 = 0, time = 0;
  double bytes_sent = 0, bytes_sent_largest = 0;  // NaN where the report has none
};

// The cycles of a report, and the report itself.
inline std::vector<Cycle> cycles_of(const JsonValue& report) {
  std::vector<Cycle> out;
  const JsonValue* list = report.find("cycles");
  if (list == nullptr) return out;
  for (const JsonValue& c : list->array) {
    Cycle r;
    const auto num = [&c](const char* key) { return c.find(key) ? c.find(key)->number : std::nan(""); };
    r.dofs = static_cast<long>(num("dofs"));
    r.triangles = static_cast<long>(num("triangles"));
    r.removals = static_cast<long>(num("removals"));
    r.estimate = num("estimate");
    r.error_l2 = num("error_l2");
    r.error_h1 = num("error_h1");
    r.time = c.find("time") ? num("time") : 0.0;
    r.bytes_sent = num("bytes_sent");
    r.bytes_sent_largest = num("bytes_sent_largest");
    out.push_back(r);
  }
  return out;
}
inline JsonValue report_of(const std::string& dir) { return JsonReader::parse(read_text(dir + "/report.json")); }

inline std::set<std::set<std::array<double, 3>>> triangles_in(const vtkSmartPointer<vtkPolyData>& pd) {
  std::set<std::set<std::array<double, 3>>> out;
  auto ids = vtkSmartPointer<vtkIdList>::New();
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) {
    pd->GetCellPoints(c, ids);
    std::set<std::array<double, 3>> corners;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
      std::array<double, 3> p;
      pd->GetPoint(ids->GetId(k), p.data());
      corners.insert(p);
    }
    out.insert(corners);
  }
  return out;
}
inline std::set<std::set<std::array<double, 3>>> triangles_of(const std::string& file) { return triangles_in(read_vtp(file)); }

}  // namespace rgbmesh::testing
