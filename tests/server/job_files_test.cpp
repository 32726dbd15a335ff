// JobDir::move: a run's artifact taken out of its directory by a rename
// where that is safe, and copied (or refused) where it is not, against the
// files as the kernel then shows them.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "jobs/job_files.h"

namespace cgview::server {
namespace {

namespace fs = std::filesystem;

class JobFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/cgview-job-files-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    root_ = tmpl;
    fs::create_directories(root_ / "work");
    fs::create_directories(root_ / "results");
  }
  void TearDown() override { fs::remove_all(root_); }
  void write(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
    ::chmod(p.c_str(), 0600);
  }
  static std::string read(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
  }
  fs::path root_;
};

TEST_F(JobFiles, AFileWithOneNameIsMovedAndMadeTheServersAnyOtherIsCopiedOrRefused) {
  write(root_ / "work" / "field.f32", "0123456789abcdef");
  const struct stat before = [&] {
    struct stat st {};
    ::stat((root_ / "work" / "field.f32").c_str(), &st);
    return st;
  }();
  const JobDir work(root_ / "work");
  std::string why;
  ASSERT_EQ(work.move("field.f32", root_ / "results" / "field.f32", 16, &why), 16u) << why;
  // The same file, no longer in the run's directory, readable by all, the server's.
  struct stat after {};
  ASSERT_EQ(::stat((root_ / "results" / "field.f32").c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino);
  EXPECT_FALSE(fs::exists(root_ / "work" / "field.f32"));
  EXPECT_EQ(after.st_mode & 07777, 0644u);
  EXPECT_EQ(after.st_uid, ::geteuid());
  EXPECT_EQ(read(root_ / "results" / "field.f32"), "0123456789abcdef");

  // A second name (a hard link the job made): copied, so that no name the
  // run kept reaches the served file.
  write(root_ / "work" / "mesh.ply", "ply bytes");
  fs::create_hard_link(root_ / "work" / "mesh.ply", root_ / "work" / "other");
  ASSERT_EQ(work.move("mesh.ply", root_ / "results" / "mesh.ply", 100, &why), 9u) << why;
  EXPECT_TRUE(fs::exists(root_ / "work" / "mesh.ply"));
  struct stat a {
  }, b{};
  ::stat((root_ / "work" / "mesh.ply").c_str(), &a);
  ::stat((root_ / "results" / "mesh.ply").c_str(), &b);
  EXPECT_NE(a.st_ino, b.st_ino);
  EXPECT_EQ(read(root_ / "results" / "mesh.ply"), "ply bytes");

  // A link, a file over its cap, a name taken: refused, nothing moved.
  fs::create_symlink(root_ / "results" / "field.f32", root_ / "work" / "link.f32");
  EXPECT_FALSE(work.move("link.f32", root_ / "results" / "link.f32", 100, &why));
  EXPECT_NE(why.find("is a link"), std::string::npos) << why;
  write(root_ / "work" / "big.f32", std::string(100, 'x'));
  EXPECT_FALSE(work.move("big.f32", root_ / "results" / "big.f32", 99, &why));
  EXPECT_NE(why.find("over the limit of 99"), std::string::npos) << why;
  EXPECT_TRUE(fs::exists(root_ / "work" / "big.f32"));
  write(root_ / "work" / "again.f32", "new");
  EXPECT_FALSE(work.move("again.f32", root_ / "results" / "field.f32", 100, &why));
  EXPECT_EQ(read(root_ / "results" / "field.f32"), "0123456789abcdef");
  EXPECT_TRUE(fs::exists(root_ / "work" / "again.f32"));
}

// spread_subdirectories: the directory marked as the top of directory
// trees ('T' as lsattr, e2fsprogs, reads the flags), where the file system
// has that flag; left as it was where it has not.
TEST_F(JobFiles, ADirectoryOfRunsIsMarkedAsTheTopOfDirectoryTrees) {
  const fs::path runs = root_ / "runs";
  fs::create_directories(runs);
  auto lsattr_flags = [&] {
    const fs::path out = root_ / "lsattr.txt";
    if (std::system(("lsattr -d '" + runs.string() + "' > '" + out.string() + "' 2>/dev/null").c_str()) != 0)
      return std::string();
    const std::string line = read(out);
    return line.substr(0, line.find(' '));
  };
  // The flag is ext2/3/4's (other file systems place directories their own way and refuse it).
  struct statfs fs_info {};
  if (::statfs(runs.c_str(), &fs_info) != 0 || fs_info.f_type != 0xEF53) GTEST_SKIP() << runs << " is not on ext2/3/4";
  const std::string before = lsattr_flags();
  if (before.empty()) GTEST_SKIP() << "lsattr cannot read the flags of " << runs << " here";
  EXPECT_EQ(before.find('T'), std::string::npos) << before;
  ASSERT_TRUE(spread_subdirectories(runs));
  const std::string after = lsattr_flags();
  EXPECT_NE(after.find('T'), std::string::npos) << after;
  // Again: still so, nothing else changed.
  EXPECT_TRUE(spread_subdirectories(runs));
  std::string expected = before;
  for (std::size_t i = 0; i < after.size() && i < expected.size(); ++i)
    if (after[i] == 'T') expected[i] = 'T';
  EXPECT_EQ(lsattr_flags(), expected);
  // Not a directory: refused.
  write(root_ / "file", "x");
  EXPECT_FALSE(spread_subdirectories(root_ / "file"));
}

}  // namespace
}  // namespace cgview::server
