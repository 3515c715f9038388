#pragma once
// Where the tests find the source tree and the CLI they run. The values live in a
// generated .cpp (cmake/build_paths.cpp.in), not in -D flags, so the compile commands
// of every test file are the same in any clone and the compiler cache can share them.

namespace rangekit::test {

// The source tree, absolute (docs/, README.md, the layout the architecture test reads).
const char* source_dir();
// The rangekit CLI of this build, absolute.
const char* cli_path();
// The project's version, as CMakeLists.txt's project() gives it.
const char* project_version();
// The interpreter the Python package is built for and the folder to put on PYTHONPATH; both
// "" in a build without the package (the sanitizer builds).
const char* python_executable();
const char* python_path();

}  // namespace rangekit::test
