// The examples' exit codes, as the tool's: bad input 2, an unwritable output 1, anything else 3,
// each with one line on stderr.
#pragma once

#include <cstdio>
#include <exception>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::examples {

template <class Body>
int run_reporting_errors(Body&& body) {
  try {
    body();
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  }
}

}  // namespace rgbmesh::examples
