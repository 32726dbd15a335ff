#include "io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "core/ascii.h"
#include "core/errors.h"
#include "io/mesh_formats.h"
#include "io/readers.h"

namespace cgview {

namespace {
std::string join_formats(bool writable) {
  std::string s;
  for (const MeshFormatInfo& f : mesh_formats())
    if (!writable || f.write) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}
}  // namespace

const char* to_string(MeshFormat f) { return mesh_format_info(f).name; }

bool can_read(MeshFormat f) { return mesh_format_info(f).read != nullptr; }
bool can_write(MeshFormat f) { return mesh_format_info(f).write != nullptr; }
std::string writable_formats() { return join_formats(true); }
std::string readable_formats() { return join_formats(false); }

MeshFormat format_from_name(const std::string& path_or_name) {
  std::string ext = path_or_name;
  const auto dot = ext.find_last_of('.');
  const auto slash = ext.find_last_of("/\\");
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) ext = ext.substr(dot + 1);
  else if (slash != std::string::npos || ext.empty())
    throw UnsupportedFormat("'" + path_or_name + "' has no extension to tell its format (one of " + readable_formats() +
                            ")");
  ext = ascii_lower(ext);
  for (const MeshFormatInfo& f : mesh_formats())
    if (ext == f.name || mesh_format_of_extension("." + ext) == &f) return f.format;
  throw UnsupportedFormat("unknown mesh format '." + ext + "' of '" + path_or_name + "' (known: " + readable_formats() +
                          ")");
}

std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path.string() + ": is a directory, not a file");
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw IoError(path.string() + ": cannot open: " + std::strerror(errno));
  std::fseek(f.get(), 0, SEEK_END);
  const long size = std::ftell(f.get());
  std::fseek(f.get(), 0, SEEK_SET);
  if (size < 0) throw IoError(path.string() + ": cannot tell its size");
  if (std::uint64_t(size) > max_bytes)
    throw InvalidInput(path.string() + ": the file has " + std::to_string(size) + " bytes, over the limit of " +
                       std::to_string(max_bytes));
  std::string bytes(std::size_t(size), '\0');
  if (size > 0 && std::fread(bytes.data(), 1, bytes.size(), f.get()) != bytes.size())
    throw IoError(path.string() + ": read error");
  return bytes;
}

ReadResult read_mesh_bytes(std::string_view bytes, MeshFormat format, const std::string& name,
                           const ReadOptions& options) {
  if (bytes.size() > options.max_bytes)
    throw InvalidInput(name + ": " + std::to_string(bytes.size()) + " bytes, over the limit of " +
                       std::to_string(options.max_bytes));
  ReadResult r;
  r.format = format;
  mesh_format_info(format).read(bytes, name, options, r);
  try {
    r.mesh.validate();
  } catch (const InvalidInput& e) {
    throw ParseError(name, e.what(), std::nullopt, std::nullopt);
  }
  return r;
}

ReadResult read_mesh_file(const std::filesystem::path& path, const ReadOptions& options) {
  const MeshFormat format = format_from_name(path.string());
  const std::string bytes = read_file_bytes(path, options.max_bytes);
  return read_mesh_bytes(bytes, format, path.string(), options);
}

Mesh read_mesh(const std::filesystem::path& path) { return read_mesh_file(path).mesh; }

std::string write_mesh_bytes(const Mesh& mesh, MeshFormat format, const WriteOptions& options) {
  mesh.validate();
  if (options.position_bits < 1 || options.position_bits > 30)
    throw InvalidInput("position quantization must be 1..30 bits, got " + std::to_string(options.position_bits));
  if (const auto write = mesh_format_info(format).write) return write(mesh, options);
  throw UnsupportedFormat(std::string("cannot write ") + to_string(format) + " (writable: " + writable_formats() + ")");
}

std::string write_ply_with_field(const Mesh& mesh, const ScalarField& field, bool binary) {
  mesh.validate();
  return detail::write_ply(mesh, binary, &field);
}

void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const WriteOptions& options) {
  write_file_bytes(path, write_mesh_bytes(mesh, format_from_name(path.string()), options));
}

void write_file_bytes(const std::filesystem::path& path, std::string_view bytes) {
  // Write beside the target and rename, so that a failure leaves no half file.
  const std::filesystem::path tmp = path.string() + ".part";
  auto fail = [&](const char* what, int err) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    const std::string msg = path.string() + ": " + what + ": " + std::strerror(err);
    if (err == ENOSPC || err == EDQUOT) throw DiskFull(msg);
    throw IoError(msg);
  };
  {
    std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(tmp.c_str(), "wb"), &std::fclose);
    if (!f) fail("cannot create", errno);
    errno = 0;
    if (std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size() || std::fflush(f.get()) != 0) {
      const int err = errno ? errno : EIO;
      f.reset();
      fail("cannot write", err);
    }
    errno = 0;
    if (std::fclose(f.release()) != 0) fail("cannot write", errno ? errno : EIO);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp);
    throw IoError(path.string() + ": cannot write: " + ec.message());
  }
}

}  // namespace cgview
