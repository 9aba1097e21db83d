# Build speed for the CI's four builds, where Eigen's and GoogleTest's headers are most of each
# object's compile time:
# - precompiled headers: cleanslam_precompile(TARGET HEADERS...) parses the heavy third-party
#   headers once per target (CMAKE_DISABLE_PRECOMPILE_HEADERS turns them off);
# - unity builds (CMAKE_UNITY_BUILD, set by the presets tools/test.sh builds; host-debug keeps one
#   object per file, for quick rebuilds and so that a missing include fails there): batches of
#   sources compiled as one object, so each batch instantiates Eigen's templates once. A fixture in
#   an anonymous namespace is then "used in a header" for GCC, hence no -Wsubobject-linkage.
set(CMAKE_UNITY_BUILD_BATCH_SIZE 8 CACHE STRING "Sources per object in unity builds")

function(cleanslam_precompile target)
  target_precompile_headers(${target} PRIVATE ${ARGN})
endfunction()

if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(cleanslam_warnings INTERFACE -Wno-subobject-linkage)
endif()
