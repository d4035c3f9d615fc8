# Every third-party package comes from Debian (scripts/setup.sh installs them).
# Pitfalls met with each are in the comments; see also NOTES in README.md.

find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)

# zstd: package codec.
find_package(zstd REQUIRED)
if(TARGET zstd::libzstd_shared)
  set(FIRELOOK_ZSTD_TARGET zstd::libzstd_shared)
else()
  set(FIRELOOK_ZSTD_TARGET zstd::libzstd_static)
endif()

# xxHash: section checksums (header-only use through XXH_INLINE_ALL).
find_path(XXHASH_INCLUDE_DIR xxhash.h REQUIRED)

# OpenVDB ships a Find module, not a config file; it needs Boost iostreams.
list(APPEND CMAKE_MODULE_PATH "/usr/lib/x86_64-linux-gnu/cmake/OpenVDB")
find_package(OpenVDB REQUIRED)

# OpenImageIO's CMake config references /usr/include/opencv4; pkg-config does not.
pkg_check_modules(OIIO REQUIRED IMPORTED_TARGET OpenImageIO)

find_package(TinyGLTF REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(glm REQUIRED)
find_package(Eigen3 REQUIRED NO_MODULE)
find_package(TBB REQUIRED)

if(FIRELOOK_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(benchmark REQUIRED)
endif()

# CLI11: the `firelook` command line (subcommands with --help each).
find_package(CLI11 REQUIRED)
