#include "io/zip_bundle.h"

#include <zip.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <system_error>

#include "io/mesh_io.h"

namespace cgview {

namespace fs = std::filesystem;

namespace {

bool unsafe_name(const std::string& n) {
  if (n.empty() || n[0] == '/' || n[0] == '\\') return true;
  if (n.size() >= 2 && n[1] == ':') return true;  // C:...
  std::size_t b = 0;
  while (b <= n.size()) {
    const std::size_t e = n.find_first_of("/\\", b);
    const std::string part = n.substr(b, e == std::string::npos ? std::string::npos : e - b);
    if (part == "..") return true;
    if (e == std::string::npos) break;
    b = e + 1;
  }
  return false;
}

// What macOS's Finder adds to a zip: __MACOSX/ and ._NAME resource forks
// (a "._spider.obj" is no second mesh).
bool macos_metadata(const std::string& n) {
  const std::size_t slash = n.find_last_of("/\\");
  return n.starts_with("__MACOSX/") || n.compare(slash == std::string::npos ? 0 : slash + 1, 2, "._") == 0;
}

struct ZipCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
struct FileCloser {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};

}  // namespace

std::vector<BundleFile> unzip_bundle(std::string_view bytes, std::size_t max_bytes, std::size_t max_files) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* src = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
  if (!src) {
    zip_error_fini(&error);
    throw InvalidInput("cannot read the zip");
  }
  // No ZIP_CHECKCONS: it refuses what unzip and every desktop tool accept,
  // as macOS's Archive Utility's zips (a local header with a data descriptor
  // that still gives the compressed size; libzip < 1.10.1).  The central
  // directory is what is read, and the bytes inflated are counted below.
  std::unique_ptr<zip_t, ZipCloser> archive(zip_open_from_source(src, ZIP_RDONLY, &error));
  if (!archive) {
    zip_source_free(src);
    const std::string why = zip_error_strerror(&error);
    zip_error_fini(&error);
    throw InvalidInput("not a readable zip: " + why);
  }
  zip_error_fini(&error);
  const zip_int64_t n = zip_get_num_entries(archive.get(), 0);
  if (n < 0 || std::size_t(n) > max_files)
    throw TooLarge("the zip holds " + std::to_string(n) + " entries, more than the " + std::to_string(max_files) +
                   " allowed");
  std::vector<BundleFile> out;
  std::size_t total = 0;
  const std::string limit = "the zip unpacks to more than the upload limit of " + std::to_string(max_bytes) + " bytes";
  for (zip_int64_t i = 0; i < n; ++i) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(archive.get(), zip_uint64_t(i), 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME))
      throw InvalidInput("the zip's entry " + std::to_string(i) + " is damaged");
    const std::string name = st.name;
    if (unsafe_name(name)) throw InvalidInput("the zip names an unsafe path '" + name + "' (absolute or with '..')");
    if (name.back() == '/' || name.back() == '\\') continue;  // a directory
    if (macos_metadata(name)) continue;
    if ((st.valid & ZIP_STAT_ENCRYPTION_METHOD) && st.encryption_method != ZIP_EM_NONE)
      throw InvalidInput("the zip's entry '" + name + "' is encrypted");
    // The declared size is checked first, then the bytes really inflated.
    if ((st.valid & ZIP_STAT_SIZE) && st.size > max_bytes - total) throw TooLarge(limit);
    std::unique_ptr<zip_file_t, FileCloser> f(zip_fopen_index(archive.get(), zip_uint64_t(i), 0));
    if (!f) throw InvalidInput("cannot open the zip's entry '" + name + "': " + zip_strerror(archive.get()));
    BundleFile file{name, {}};
    char buf[1 << 16];
    for (;;) {
      const zip_int64_t got = zip_fread(f.get(), buf, sizeof buf);
      if (got < 0) throw InvalidInput("the zip's entry '" + name + "' is damaged: " + zip_file_strerror(f.get()));
      if (got == 0) break;
      total += std::size_t(got);
      if (total > max_bytes) throw TooLarge(limit);
      file.bytes.append(buf, std::size_t(got));
    }
    out.push_back(std::move(file));
  }
  return out;
}

const BundleFile& bundle_mesh_file(const std::vector<BundleFile>& files) {
  std::vector<const BundleFile*> meshes;
  for (const auto& f : files) {
    try {
      if (can_read(format_from_name(f.name))) meshes.push_back(&f);
    } catch (const UnsupportedFormat&) {
      // an MTL, an image, a readme
    }
  }
  if (meshes.empty()) throw InvalidInput("the zip holds no mesh file (readable: " + readable_formats() + ")");
  if (meshes.size() > 1)
    throw InvalidInput("the zip holds several mesh files ('" + meshes[0]->name + "', '" + meshes[1]->name +
                       "', ...): upload one mesh per zip");
  return *meshes.front();
}

namespace {

std::string read_zip_file(const fs::path& zip, std::size_t max_bytes) {
  std::error_code ec;
  const auto size = fs::file_size(zip, ec);
  if (ec) throw IoError(zip.string() + ": " + ec.message());
  if (size > max_bytes)
    throw InvalidInput(zip.string() + " is larger than the limit of " + std::to_string(max_bytes) + " bytes");
  std::ifstream in(zip, std::ios::binary);
  if (!in) throw IoError(zip.string() + ": cannot open");
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), std::streamsize(size))) throw IoError(zip.string() + ": cannot read");
  return bytes;
}

}  // namespace

BundleDir::BundleDir(const fs::path& zip, std::size_t max_bytes) {
  std::vector<BundleFile> files;
  try {
    files = unzip_bundle(read_zip_file(zip, max_bytes), max_bytes);
  } catch (const TooLarge& e) {
    throw TooLarge(zip.string() + ": " + e.what());
  } catch (const InvalidInput& e) {
    throw InvalidInput(zip.string() + ": " + e.what());
  }
  const BundleFile* mesh = nullptr;
  try {
    mesh = &bundle_mesh_file(files);
  } catch (const InvalidInput& e) {
    throw InvalidInput(zip.string() + ": " + e.what());
  }
  std::string templ = (fs::temp_directory_path() / "cgview-bundle-XXXXXX").string();
  if (!mkdtemp(templ.data())) throw IoError("cannot make a temporary directory: " + std::string(std::strerror(errno)));
  dir_ = templ;
  try {
    // unzip_bundle refused absolute names and "..": every path stays under dir_.
    for (const auto& f : files) {
      const fs::path p = dir_ / fs::path(f.name).relative_path();
      fs::create_directories(p.parent_path());
      std::ofstream out(p, std::ios::binary | std::ios::trunc);
      if (!out.write(f.bytes.data(), std::streamsize(f.bytes.size())) || !out.flush())
        throw IoError("cannot write " + p.string());
      if (&f == mesh) mesh_path_ = p;
    }
  } catch (const fs::filesystem_error& e) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    throw IoError(zip.string() + ": cannot unpack: " + e.what());
  } catch (...) {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    throw;
  }
  mesh_entry_ = mesh->name;
}

BundleDir::~BundleDir() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

}  // namespace cgview
