# Unity builds (CMAKE_UNITY_BUILD, set by the four presets tools/test.sh builds; host-debug keeps
# one object per file, for quick rebuilds and so that a missing include fails there): batches of
# sources compiled as one object, so that a batch parses Eigen's and GoogleTest's headers and
# instantiates Eigen's templates once, which is most of each object's compile time. A fixture in
# an anonymous namespace is then "used in a header" for GCC, hence no -Wsubobject-linkage.
set(CMAKE_UNITY_BUILD_BATCH_SIZE 16 CACHE STRING "Sources per object in unity builds")

if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  target_compile_options(cleanslam_warnings INTERFACE -Wno-subobject-linkage)
endif()
