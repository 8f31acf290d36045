#pragma once
// What the CLI tests read from an adapt run: the report's cycles, and a cycle file's triangles
// by their corners' positions (to compare meshes without their numbering).

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
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
  double coarsening_rounds = 0, exchanges = 0;    // NaN where the report has none
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
    r.coarsening_rounds = num("coarsening_rounds");
    r.exchanges = num("exchanges");
    out.push_back(r);
  }
  return out;
}
inline JsonValue report_of(const std::string& dir) { return JsonReader::parse(read_text(dir + "/report.json")); }
// Every value of `key` in a report's text as printed, in order: for comparing two runs digit
// for digit.
inline std::vector<std::string> printed_values(const std::string& text, const std::string& key) {
  std::vector<std::string> out;
  const std::string pattern = "\"" + key + "\": ";
  for (std::size_t at = 0; (at = text.find(pattern, at)) != std::string::npos; ++at)
    out.push_back(text.substr(at + pattern.size(), text.find_first_of(",}", at) - at - pattern.size()));
  return out;
}

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

/// The triangles of `b` that `a` does not have and those of `a` that `b` does not have, a
/// corner of one matching a point of the other within `tolerance` in each coordinate (the
/// processes of a distributed mesh compute some limit positions in another order: the last
/// bit may differ). Two counts, both 0 for the same triangles.
inline std::array<std::size_t, 2> triangles_differing(const vtkSmartPointer<vtkPolyData>& a,
                                                      const vtkSmartPointer<vtkPolyData>& b, double tolerance = 1e-12) {
  // a's points on a grid of cells of side 1e-6: a point of b is looked for in its cell and the
  // neighbouring ones.
  const double cell = 1e-6;
  const auto key = [cell](const double* p, int dx, int dy, int dz) {
    return std::array<long long, 3>{static_cast<long long>(std::floor(p[0] / cell)) + dx,
                                    static_cast<long long>(std::floor(p[1] / cell)) + dy,
                                    static_cast<long long>(std::floor(p[2] / cell)) + dz};
  };
  std::map<std::array<long long, 3>, std::vector<vtkIdType>> grid;
  for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i) grid[key(a->GetPoint(i), 0, 0, 0)].push_back(i);
  const auto match = [&](const double* p) -> vtkIdType {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(key(p, dx, dy, dz));
          if (it == grid.end()) continue;
          for (const vtkIdType i : it->second) {
            double q[3];
            a->GetPoint(i, q);
            if (std::abs(q[0] - p[0]) <= tolerance && std::abs(q[1] - p[1]) <= tolerance && std::abs(q[2] - p[2]) <= tolerance)
              return i;
          }
        }
    return -1;
  };
  const auto cells_of = [](const vtkSmartPointer<vtkPolyData>& pd, const auto& id_of) {
    std::set<std::array<vtkIdType, 3>> out;
    auto ids = vtkSmartPointer<vtkIdList>::New();
    for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c) {
      pd->GetCellPoints(c, ids);
      std::array<vtkIdType, 3> t{id_of(ids->GetId(0)), id_of(ids->GetId(1)), id_of(ids->GetId(2))};
      std::sort(t.begin(), t.end());
      out.insert(t);
    }
    return out;
  };
  const auto in_a = cells_of(a, [](vtkIdType i) { return i; });
  const auto in_b = cells_of(b, [&](vtkIdType i) { return match(b->GetPoint(i)); });
  std::array<std::size_t, 2> differ{0, 0};
  for (const auto& t : in_b) differ[0] += (t[0] < 0 || !in_a.count(t)) ? 1 : 0;
  for (const auto& t : in_a) differ[1] += in_b.count(t) ? 0 : 1;
  return differ;
}

// The run folder `dir` as an interruption after `k` cycles (steps) would have left it: the
// report lists k, says "running", and the later files are gone.
inline void interrupt_after(const std::string& dir, int k, const char* prefix) {
  std::string json = read_text(dir + "/report.json");
  const auto list = json.find("\"cycles\": [");
  ASSERT_NE(list, std::string::npos);
  const auto cut = json.find(", {\"cycle\": " + std::to_string(k) + ",", list);
  ASSERT_NE(cut, std::string::npos);
  json = json.substr(0, cut) + "]}\n";
  const auto status = json.find("\"status\": \"finished\"");
  ASSERT_NE(status, std::string::npos);
  json.replace(status, 20, "\"status\": \"running\"");
  std::ofstream(dir + "/report.json") << json;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && std::stoi(name.substr(std::string(prefix).size())) >= k)
      fs::remove(e.path());
  }
}

}  // namespace rgbmesh::testing
