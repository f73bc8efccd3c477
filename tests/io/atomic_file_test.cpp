#include "mspline/io/atomic_file.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "mspline/structure/core/errors.h"
#include "support/test_data.h"

namespace {

namespace fs = std::filesystem;
using mspline::io::OutputBatch;
using mspline::io::writeFileAtomically;

std::size_t entries(const std::string& dir) {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++count;
  return count;
}

void writeText(const std::string& path, const std::string& text) {
  writeFileAtomically(path, [&](std::ostream& out) { out << text; });
}

unsigned permissions(const std::string& path) {
  struct stat status {};
  REQUIRE(::stat(path.c_str(), &status) == 0);
  return status.st_mode & 07777;
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

TEST_CASE("atomic_file: a symbolic link is written through and the permissions are kept", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_link_mode");
  writeText(dir + "/real.txt", "old");
  REQUIRE(::chmod((dir + "/real.txt").c_str(), 0600) == 0);
  fs::create_symlink("real.txt", dir + "/link.txt");
  writeText(dir + "/link.txt", "new");
  CHECK(fs::is_symlink(dir + "/link.txt"));
  CHECK(mspline::test::fileText(dir + "/real.txt") == "new");
  CHECK(permissions(dir + "/real.txt") == 0600);
  CHECK(entries(dir) == 2);

  // A dangling link creates its target.
  fs::create_symlink("made.txt", dir + "/dangling.txt");
  writeText(dir + "/dangling.txt", "made");
  CHECK(fs::is_symlink(dir + "/dangling.txt"));
  CHECK(mspline::test::fileText(dir + "/made.txt") == "made");

  // A device is written in place, not replaced.
  CHECK_NOTHROW(writeText("/dev/null", "nothing"));
  CHECK(fs::is_character_file("/dev/null"));
}

TEST_CASE("atomic_file: a batch replaces all of its targets or none", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_batch");
  writeText(dir + "/a.txt", "old a");
  {
    OutputBatch batch;
    writeText(dir + "/a.txt", "new a");
    CHECK(mspline::test::fileText(dir + "/a.txt") == "old a");
    CHECK_THROWS(writeFileAtomically(dir + "/b.txt", [](std::ostream& out) {
      out << "half";
      throw std::runtime_error("second output failed");
    }));
  }  // not committed
  CHECK(mspline::test::fileText(dir + "/a.txt") == "old a");
  CHECK(entries(dir) == 1);

  {
    OutputBatch outer;
    {
      OutputBatch inner;
      writeText(dir + "/b.txt", "b");
      inner.commit();
    }
    CHECK(!fs::exists(dir + "/b.txt"));  // the inner batch hands its file to the outer one
    writeText(dir + "/a.txt", "new a");
    outer.commit();
  }
  CHECK(mspline::test::fileText(dir + "/a.txt") == "new a");
  CHECK(mspline::test::fileText(dir + "/b.txt") == "b");
  CHECK(entries(dir) == 2);
}

TEST_CASE("atomic_file: a killed writer leaves the old file and nothing else", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_kill");
  const std::string path = dir + "/out.txt";
  writeText(path, "old");
  for (int delayMs : {0, 5, 20}) {
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      writeFileAtomically(path, [](std::ostream& out) {
        for (;;) out << std::string(1 << 16, 'x');  // until killed
      });
      ::_exit(0);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    CHECK(WIFSIGNALED(status));
    CHECK(mspline::test::fileText(path) == "old");
    CHECK(entries(dir) == 1);
  }
}

TEST_CASE("atomic_file: temporaries named by a process that is gone are removed", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_stale");
  // A pid above the kernel's largest (4194304) belongs to no process.
  const std::string gone = dir + "/.out.txt.mspline-99999999-0.tmp";
  const std::string alive = dir + "/.out.txt.mspline-" + std::to_string(::getppid()) + "-0.tmp";
  const std::string other = dir + "/.other.txt.mspline-99999999-0.tmp";
  for (const std::string& name : {gone, alive, other}) std::ofstream(name) << "left";
  writeText(dir + "/out.txt", "new");
  CHECK(!fs::exists(gone));
  CHECK(fs::exists(alive));
  CHECK(fs::exists(other));
  CHECK(mspline::test::fileText(dir + "/out.txt") == "new");
}

TEST_CASE("atomic_file: a batch's file can be read before it is named", "[io]") {
  std::string dir = mspline::test::scratchDirectory("atomic_file_readable");
  const std::string path = dir + "/out.txt";
  OutputBatch batch;
  CHECK(batch.readablePath(path) == path);
  writeText(path, "staged");
  CHECK(!fs::exists(path));
  CHECK(mspline::test::fileText(batch.readablePath(path)) == "staged");
  batch.commit();
  CHECK(mspline::test::fileText(path) == "staged");
}
