# Strict warnings for the project's own targets; third-party headers come in as SYSTEM.
add_library(cleanslam_warnings INTERFACE)
target_compile_options(cleanslam_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Wunused -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion -Wformat=2
  $<$<BOOL:${CLEANSLAM_WERROR}>:-Werror>)

# -g1 (line tables) after the build type's -g: reports keep file:line, and the Eigen-heavy objects
# compile about 14 % faster (test_ekf.cpp: 55.6 s against 48.0 s). Optimized, because unoptimized
# Eigen under the sanitizers made the tests the suite's larger half (232 s of tests at -O0 against
# 39 s at -O1, on 2 cores). -Og rather than -O1: the Eigen-heavy files compile 17-20 % faster
# (test_ekf.cpp 41.9 s against 33.6 s, ekf.cpp 55.2 s against 46.4 s) for tests about 15 % slower
# (86 s of test time against 73 s).
if(CLEANSLAM_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
                      -g1 -Og)
  add_link_options(-fsanitize=address,undefined)
endif()

# libFuzzer builds (preset host-fuzz, clang): every object instrumented for the sanitizers and the
# project's own code for coverage; the fuzz targets link libFuzzer's main (tests/fuzz). Eigen's and
# the standard library's out-of-line functions are left out of the coverage (their loop counters
# and comparisons guide nothing and cost each input most of its time), and UBSan's memory checks,
# which ASan covers, out of Eigen's functions: their code kept Eigen's one-line functions from
# being inlined (tests/fuzz/sanitizer_ignorelist.txt says what stays checked).
if(CLEANSLAM_LIBFUZZER)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fsanitize-coverage-ignorelist=${CMAKE_SOURCE_DIR}/tests/fuzz/coverage_ignorelist.txt
                      -fsanitize-ignorelist=${CMAKE_SOURCE_DIR}/tests/fuzz/sanitizer_ignorelist.txt
                      -fno-sanitize-recover=all -g -O1)
  add_link_options(-fsanitize=address,undefined)
endif()

# cleanslam_part(NAME ...) gives a project target the warnings; every part and tool uses it.
function(cleanslam_warnings target)
  target_link_libraries(${target} PRIVATE cleanslam_warnings)
endfunction()
