#include "mspline/io/atomic_file.h"

#include <catch2/catch.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mspline/structure/core/errors.h"
#include "support/test_data.h"

namespace {

namespace fs = std::filesystem;
using mspline::io::writeFileAtomically;

std::size_t entries(const std::string& dir) {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++count;
  return count;
}

}  // namespace

TEST_CASE("atomic_file: writes and replaces the target, leaving no temporary", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_success");
  std::string path = dir + "/out.txt";
  writeFileAtomically(path, [](std::ostream& out) { out << "first\n"; });
  CHECK(mspline::test::fileText(path) == "first\n");
  writeFileAtomically(path, [](std::ostream& out) { out.write("sec\0nd", 6); });
  CHECK(mspline::test::fileText(path) == std::string("sec\0nd", 6));
  CHECK(entries(dir) == 1);
}

TEST_CASE("atomic_file: a throwing writer leaves the target untouched", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_throw");
  std::string path = dir + "/out.txt";
  auto failing = [](std::ostream& out) {
    out << std::string(100000, 'x');
    throw std::range_error("writer gave up");
  };
  CHECK_THROWS_AS(writeFileAtomically(path, failing), std::range_error);
  CHECK(entries(dir) == 0);

  writeFileAtomically(path, [](std::ostream& out) { out << "kept"; });
  CHECK_THROWS_WITH(writeFileAtomically(path, failing), "writer gave up");
  CHECK(mspline::test::fileText(path) == "kept");
  CHECK(entries(dir) == 1);
}

TEST_CASE("atomic_file: system failures are IoErrors naming the path", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_system");
  std::string missing = dir + "/no/such/dir/out.txt";
  bool called = false;
  auto write = [&](std::ostream& out) {
    called = true;
    out << "x";
  };
  CHECK_THROWS_AS(writeFileAtomically(missing, write), mspline::structure::IoError);
  CHECK_THROWS_WITH(writeFileAtomically(missing, write),
                    Catch::Contains(missing) && Catch::Contains(std::strerror(ENOENT)));
  CHECK(!called);
  CHECK(entries(dir) == 0);

  // Renaming a file onto a non-empty directory fails after the data was written.
  fs::create_directories(dir + "/occupied/child");
  CHECK_THROWS_AS(writeFileAtomically(dir + "/occupied", write), mspline::structure::IoError);
  CHECK(called);
  CHECK(entries(dir) == 1);
  CHECK(fs::is_directory(dir + "/occupied/child"));
}
