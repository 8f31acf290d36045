# rgbmesh_warnings(target): the project builds clean with -Wall -Wextra.
function(rgbmesh_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor)
endfunction()
