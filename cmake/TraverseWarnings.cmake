# Project code compiles warning-free under -Wall -Wextra; third-party headers are SYSTEM.
add_library(traverse_warnings INTERFACE)
target_compile_options(traverse_warnings INTERFACE -Wall -Wextra)
if(TRAVERSE_SANITIZE)
  # Optimisation and debug info of the sanitized tree, placed after the build type's flags so
  # they win (RelWithDebInfo's -O2 -g becomes -O1 -g1, -DNDEBUG stays). Measured with gcc 12
  # on a Trilinos-heavy source (docs/reliability.md, "Sanitizers"): -O1 -g1 compiles 2.4x
  # faster than -O2 -g and runs the tests about 10 % slower; -Og compiles faster still but
  # runs them about 35 % slower. -g1 keeps file:line in sanitizer stacks. Empty: the build
  # type's flags.
  set(TRAVERSE_SANITIZE_OPT_FLAGS "-O1 -g1" CACHE STRING
      "Optimisation/debug flags appended in a TRAVERSE_SANITIZE build (empty: the build type's)")
  separate_arguments(_traverse_sanitize_opt UNIX_COMMAND "${TRAVERSE_SANITIZE_OPT_FLAGS}")
  target_compile_options(traverse_warnings INTERFACE ${_traverse_sanitize_opt}
    -fsanitize=address,undefined -fno-omit-frame-pointer)
  target_link_options(traverse_warnings INTERFACE -fsanitize=address,undefined)
endif()

# libFuzzer build (clang only): instruments every project target for coverage and with
# AddressSanitizer + UndefinedBehaviorSanitizer; the fuzz targets live in tests/fuzz/.
# Configure in a separate tree, e.g. (docs/reliability.md):
#   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DTRAVERSE_FUZZ=ON && make -C build-fuzz fuzz_scene
option(TRAVERSE_FUZZ "Build the libFuzzer targets (needs clang and libclang-rt-*-dev)" OFF)
if(TRAVERSE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "TRAVERSE_FUZZ needs clang (CC=clang CXX=clang++), found ${CMAKE_CXX_COMPILER_ID}")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -g)
  add_link_options(-fsanitize=address,undefined)
endif()
