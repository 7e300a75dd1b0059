/// @file test_hardening.cpp
/// Failures found by fuzzing and fault injection, each of which must end cleanly: a typed error
/// (InputError, exit 2; IoError, exit 4) with a message naming the file, no crash, no hang and no
/// output left behind. Reads that used to crash or block run in a child process with a time limit,
/// so that on a regression the test fails instead of crashing or stalling the suite.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <new>
#include <typeinfo>

#include "common/atomic_file.hpp"
#include "common/cli.hpp"
#include "common/h5.hpp"
#include "common/status.hpp"
#include "test_util.hpp"

namespace fs = std::filesystem;
using namespace common;

namespace {

/// How a call ended: kind is "ok", "InputError", "IoError", "other", "crash" or "hang".
struct Ending {
  std::string kind, what;
  double seconds = 0;
};

Ending in_child(const std::function<void()>& body, double limit_s = 30) {
  int fds[2];
  EXPECT_EQ(::pipe(fds), 0);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    std::string out;
    try {
      body();
      out = "ok\n";
    } catch (const InputError& e) {
      out = std::string("InputError\n") + e.what();
    } catch (const IoError& e) {
      out = std::string("IoError\n") + e.what();
    } catch (const std::exception& e) {
      out = std::string("other\n") + typeid(e).name() + ": " + e.what();
    }
    if (::write(fds[1], out.data(), out.size()) < 0) ::_exit(3);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string got;
  const auto deadline = t0 + std::chrono::duration<double>(limit_s);
  bool hung = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      hung = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left)) <= 0) continue;
    char buf[4096];
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n <= 0) break;
    got.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (hung) ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  Ending e;
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (hung) {
    e.kind = "hang";
  } else if (WIFSIGNALED(status)) {
    e.kind = "crash";
    e.what = "signal " + std::to_string(WTERMSIG(status));
  } else {
    const auto nl = got.find('\n');
    e.kind = got.substr(0, nl);
    e.what = nl == std::string::npos ? "" : got.substr(nl + 1);
  }
  return e;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

std::string long_name() { return std::string(300, 'x') + ".h5"; }

}  // namespace

// ---- 1. corrupt HDF5 files: crash (SIGSEGV in H5HG_read) or endless loop inside libhdf5 -------

// Mutants found by test_fuzz (seeded byte flips of small valid files) that crashed or hung all
// readers before the readers validated files in a child process.
TEST(Hardening, CorruptHdf5FilesAreRejectedWithinBoundedTime) {
  const fs::path data = fs::path(SUITE_SOURCE_DIR) / "tests/common/data";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(data))
    if (e.path().extension() == ".h5") files.push_back(e.path());
  ASSERT_GE(files.size(), 2u);
  ::setenv("SUITE_H5_CHECK_TIMEOUT_S", "2", 1);
  for (const auto& f : files) {
    const std::string p = f.string();
    const std::vector<std::pair<const char*, std::function<void()>>> readers = {
        {"read_particle_snapshot", [&] { read_particle_snapshot(p); }},
        {"read_sphere_set", [&] { read_sphere_set(p); }},
        {"read_provenance", [&] {
           h5::Handle h = h5::open_file_read(p);
           h5::read_provenance(h, p);
         }}};
    for (const auto& [name, read] : readers) {
      const Ending e = in_child(read, 20);
      SCOPED_TRACE(f.filename().string() + " " + name);
      EXPECT_EQ(e.kind, "InputError") << e.what;
      EXPECT_NE(e.what.find(p), std::string::npos) << e.what;
      EXPECT_NE(e.what.find("corrupt or unreadable HDF5 file"), std::string::npos) << e.what;
      EXPECT_LT(e.seconds, 10.0);
    }
  }
}

// ---- 2. a FIFO as an input file blocked forever ----------------------------------------------

TEST(Hardening, FifoInputIsRefused) {
  testutil::TempDir dir;
  const std::string fifo = dir.file("in.h5");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const auto& read : std::vector<std::function<void()>>{[&] { read_particle_snapshot(fifo); },
                                                             [&] { read_sphere_set(fifo); },
                                                             [&] { Scene::load(Schema("x"), fifo); }}) {
    const Ending e = in_child(read, 5);
    EXPECT_EQ(e.kind, "InputError") << e.what;
    EXPECT_NE(e.what.find(fifo), std::string::npos) << e.what;
    EXPECT_NE(e.what.find("not a regular file"), std::string::npos) << e.what;
  }
  EXPECT_EQ(names_in(dir.path), std::vector<std::string>{"in.h5"});
}

// ---- 3. an output path that is a FIFO or a device node was replaced by a regular file ---------

TEST(Hardening, OutputThatIsNotARegularFileIsRefused) {
  testutil::TempDir dir;
  std::vector<std::string> specials = {dir.file("out.h5")};
  ASSERT_EQ(::mkfifo(specials[0].c_str(), 0600), 0);
  if (::geteuid() == 0) {  // a copy of /dev/null (char 1:3)
    specials.push_back(dir.file("null.h5"));
    ASSERT_EQ(::mknod(specials[1].c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);
  }
  const auto before = names_in(dir.path);
  for (const auto& out : specials) {
    const std::vector<std::function<void()>> writers = {
        [&] { write_sphere_set(out, testutil::sample_spheres(4), testutil::sample_provenance()); },
        [&] { write_particle_snapshot(out, testutil::sample_particles(4), testutil::sample_provenance()); },
        [&] { write_text_atomic(out, "text"); },
        [&] { PartialFile series(out); }};
    for (const auto& w : writers) {
      const Ending e = in_child(w, 5);
      EXPECT_EQ(e.kind, "InputError") << e.what;
      EXPECT_NE(e.what.find(out), std::string::npos) << e.what;
      EXPECT_NE(e.what.find("not a regular file"), std::string::npos) << e.what;
    }
    struct stat st {};
    ASSERT_EQ(::stat(out.c_str(), &st), 0);
    EXPECT_FALSE(S_ISREG(st.st_mode)) << out << " was replaced by a regular file";
  }
  EXPECT_EQ(names_in(dir.path), before);  // no temporary, partial or sidecar file left
}

// ---- 4. filesystem_error and bad_alloc ended as "internal error" (exit 1) ----------------------

TEST(Hardening, OverlongPathComponentIsBadInput) {
  testutil::TempDir dir;
  const std::string in = dir.file(long_name());
  const Ending r = in_child([&] { read_particle_snapshot(in); });
  EXPECT_EQ(r.kind, "InputError") << r.what;
  EXPECT_NE(r.what.find("File name too long"), std::string::npos) << r.what;
  // An output that cannot be created is an I/O failure (exit 4), as for an output directory.
  const Ending w = in_child([&] { write_sphere_set(in, testutil::sample_spheres(4), testutil::sample_provenance()); });
  EXPECT_EQ(w.kind, "IoError") << w.what;
  EXPECT_NE(w.what.find(in), std::string::npos) << w.what;
  EXPECT_NE(w.what.find("File name too long"), std::string::npos) << w.what;
  EXPECT_TRUE(names_in(dir.path).empty());
  // A final name just under NAME_MAX: the temporary name must still fit.
  const std::string near_max = dir.file(std::string(250, 'y') + ".h5");
  write_sphere_set(near_max, testutil::sample_spheres(4), testutil::sample_provenance());
  EXPECT_EQ(read_sphere_set(near_max).count(), 4u);
}

TEST(Hardening, ToolAppMapsFilesystemErrorAndBadAlloc) {
  auto run_with = [](const std::function<void()>& thrower) {
    ToolApp app("t", "test", Schema("t"), false);
    char a0[] = "t";
    char* argv[] = {a0, nullptr};
    return app.run(1, argv, [&](const Scene&, const Provenance&) {
      thrower();
      return 0;
    });
  };
  EXPECT_EQ(run_with([] { (void)fs::status(std::string(300, 'z') + "/x"); }), 2);  // ENAMETOOLONG: bad input
  EXPECT_EQ(run_with([] {
              throw fs::filesystem_error("create", "/ro", std::make_error_code(std::errc::read_only_file_system));
            }),
            4);
  EXPECT_EQ(run_with([] { throw std::bad_alloc(); }), 4);
}

TEST(Hardening, DeclaredDatasetLargerThanTheFileIsRejectedBeforeAllocating) {
  testutil::TempDir dir;
  const std::string path = dir.file("huge.h5");
  write_particle_snapshot(path, testutil::sample_particles(4), testutil::sample_provenance());
  {
    h5::quiet_errors();
    h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
    H5Ldelete(f, "/particles/id", H5P_DEFAULT);
    const hsize_t rows = hsize_t{1} << 40;  // declared, never written (late allocation)
    h5::Handle space(H5Screate_simple(1, &rows, nullptr));
    h5::Handle ds(H5Dcreate2(f, "/particles/id", H5T_STD_U64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
    ASSERT_TRUE(ds.valid());
  }
  const Ending e = in_child([&] { read_particle_snapshot(path); });
  EXPECT_EQ(e.kind, "InputError") << e.what;
  EXPECT_NE(e.what.find(path), std::string::npos) << e.what;
  EXPECT_NE(e.what.find("/particles/id"), std::string::npos) << e.what;
  EXPECT_NE(e.what.find("more than the whole file holds"), std::string::npos) << e.what;
}

// ---- 5. duplicate ids were accepted ------------------------------------------------------------

TEST(Hardening, DuplicateIdsAreRejected) {
  testutil::TempDir dir;
  auto p = testutil::sample_particles(10);
  p.id.assign(10, 7);
  write_particle_snapshot(dir.file("p.h5"), p, testutil::sample_provenance());
  auto s = testutil::sample_spheres(10);
  for (std::size_t i = 0; i < 10; ++i) s.id[i] = 100 - i;  // not sorted: the O(n log n) path
  s.id[6] = s.id[2];
  write_sphere_set(dir.file("s.h5"), s, testutil::sample_provenance());
  const Ending ep = in_child([&] { read_particle_snapshot(dir.file("p.h5")); });
  EXPECT_EQ(ep.kind, "InputError");
  EXPECT_NE(ep.what.find(dir.file("p.h5") + ": /particles/id: duplicate id 7 at rows 0 and 1"), std::string::npos)
      << ep.what;
  const Ending es = in_child([&] { read_sphere_set(dir.file("s.h5")); });
  EXPECT_EQ(es.kind, "InputError");
  EXPECT_NE(es.what.find(dir.file("s.h5") + ": /spheres/id: duplicate id 98 at rows 2 and 6"), std::string::npos)
      << es.what;
}

// ---- 6. datasets the readers did not read were not validated ---------------------------------

TEST(Hardening, EveryDatasetOfTheItemGroupIsValidated) {
  struct Case {
    const char* name;
    std::function<void(hid_t)> edit;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {"uint8 dataset", [](hid_t f) {
         const hsize_t d[2] = {10, 6};
         h5::Handle space(H5Screate_simple(2, d, nullptr));
         h5::Handle ds(H5Dcreate2(f, "/particles/flags", H5T_STD_U8LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
         std::vector<unsigned char> v(60, 1);
         H5Dwrite(ds, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
       }, "/particles/flags: wrong dtype: extra datasets (fields) must be float64"},
      {"(N,1) id", [](hid_t f) {
         H5Ldelete(f, "/particles/id", H5P_DEFAULT);
         std::vector<std::uint64_t> id(10);
         for (std::size_t i = 0; i < 10; ++i) id[i] = i;
         const hsize_t d[2] = {10, 1};
         h5::Handle space(H5Screate_simple(2, d, nullptr));
         h5::Handle ds(H5Dcreate2(f, "/particles/id", H5T_STD_U64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
         H5Dwrite(ds, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, id.data());
       }, "/particles/id: wrong shape (10, 1), expected (N,)"},
      {"(N,1) mass", [](hid_t f) {
         H5Ldelete(f, "/particles/mass", H5P_DEFAULT);
         std::vector<double> m(10, 1.0);
         const hsize_t d[2] = {10, 1};
         h5::Handle space(H5Screate_simple(2, d, nullptr));
         h5::Handle ds(H5Dcreate2(f, "/particles/mass", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
         H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data());
       }, "/particles/mass: wrong shape (10, 1), expected (10,)"},
      {"sub-group", [](hid_t f) { h5::create_group(f, "/particles/extra"); },
       "/particles/extra: not a dataset"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    testutil::TempDir dir;
    const std::string path = dir.file("bad.h5");
    write_particle_snapshot(path, testutil::sample_particles(10), testutil::sample_provenance());
    {
      h5::quiet_errors();
      h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
      c.edit(f);
    }
    const Ending e = in_child([&] { read_particle_snapshot(path); });
    EXPECT_EQ(e.kind, "InputError") << e.what;
    EXPECT_NE(e.what.find(path + ": " + c.expect), std::string::npos) << e.what;
  }
  // Still accepted: a float64 field of shape (N,) or (N, k).
  testutil::TempDir dir;
  auto p = testutil::sample_particles(10);
  p.fields.push_back({"temperature", "K", 1, std::vector<double>(10, 300.0), ""});
  write_particle_snapshot(dir.file("ok.h5"), p, testutil::sample_provenance());
  EXPECT_EQ(read_particle_snapshot(dir.file("ok.h5")).field("temperature")->ncomp, 1u);
}
