#pragma once
// Public meshes and point clouds that the repository does not hold, fetched into the build
// tree by scripts/fetch-test-data.sh (the test command runs it).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace rgbmesh::testing {

// The path of a public data file; the test fails (not skips) when it is missing, so that CI
// never passes without the data.
inline std::string public_data(const std::string& name) {
  const std::string path = std::string(RGBMESH_PUBLIC_DATA_DIR) + "/" + name;
  if (!std::filesystem::exists(path))
    ADD_FAILURE() << "missing public test data " << path << ": run scripts/fetch-test-data.sh";
  return path;
}

}  // namespace rgbmesh::testing
