// Reading an upload: the bytes of a mesh file, or of a zip of one with its
// MTL and images, turned into what the store keeps of a mesh (its report,
// warnings and materials) and the files it keeps (the mesh file, textures).
// Everything here touches the untrusted bytes; the server runs it in a child
// process (read_upload_in_child) so that whatever a file does to a parser
// costs that child, not the server.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"
#include "sandbox.h"

namespace cgview::server {

struct UploadRead {
  std::string name;    // the mesh file's name (a zip's mesh file: its base name)
  std::string format;  // "ply", ...
  // The mesh file's bytes when they are not the upload's (a zip's mesh file);
  // empty when the upload is the mesh file.
  std::string unpacked_mesh;
  std::string report_json, warnings_json, material_json;
  std::vector<std::string> textures;  // one blob per material_json "textures" entry
  std::shared_ptr<const Mesh> mesh;   // the mesh, when read in this process
};

// Throws InvalidInput when the name is empty, longer than 255 bytes or holds
// '/', '\\' or a control character; else returns it.
std::string clean_upload_name(const std::string& name);

// Reads an upload in this process (format given, or from the name's
// extension; "zip" or a ".zip" name is a bundle).  Throws InvalidInput (bad
// name, format or file), UnsupportedFormat, TooLarge (a zip unpacking past
// max_unpacked_bytes).  A file the mesh refers to that is missing is a
// warning, not an error.
UploadRead read_upload(const std::string& name, const std::string& format, std::string_view bytes,
                       std::size_t max_unpacked_bytes);

// Where and within what an upload is read in a child process.
struct UploadReader {
  std::filesystem::path program;   // cgview-read; empty: read in this process
  std::filesystem::path temp_dir;  // the child's files (the upload, its results), one directory per upload
  std::size_t memory_mb = 8192;    // the child's address space; 0: no limit
  std::chrono::milliseconds time_limit{120000};
  // The jobs' sandbox: a file's parser is as exposed to its bytes as a job
  // to its code, so a reader sees only its own directory, never the data
  // directory (`hidden`).  Null or off: a plain child.
  std::shared_ptr<const Sandbox> sandbox;
  std::filesystem::path hidden;
};

// read_upload run by `reader.program --read-upload DIR` (cgview-read) in a child process
// with the reader's memory and time limits.  Throws what read_upload throws
// (its message carried over), TooLarge when the child goes over the memory
// or time limit, InvalidInput when it dies otherwise (a crash in a parser:
// the file is refused, the server goes on) and IoError when the child cannot
// be run.  The result has no `mesh`.
UploadRead read_upload_in_child(const UploadReader& reader, const std::string& name, const std::string& format,
                                std::string_view bytes, std::size_t max_unpacked_bytes);

// A directory of its own for one read in a child, removed with its files.
class ReadDir {
 public:
  explicit ReadDir(const std::filesystem::path& parent);  // throws IoError
  ~ReadDir();
  ReadDir(const ReadDir&) = delete;
  ReadDir& operator=(const ReadDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A file the reader child wrote into `dir`, read as a job's files are
// (jobs/job_files.h): beneath it, through no link, a regular file, at most
// `cap` bytes; throws std::runtime_error saying what was wrong with it.
std::string child_file(const ReadDir& dir, const std::string& name, std::uint64_t cap);

// Runs `reader.program MODE DIR` (cgview-read) on what the caller put in DIR
// (the upload, request.json) under the reader's limits, and returns when it
// read the file (its results in DIR).  Otherwise throws as the read would
// have (the child's error.json: its kind and its message), TooLarge over a
// limit, InvalidInput when the child dies (`name` in the message), IoError
// when it cannot run.
void run_reader_child(const UploadReader& reader, const char* mode, const std::string& name, const ReadDir& dir);

// The child's side of any read: runs `read`, and turns what it throws into
// DIR/error.json ({"error": kind, "detail"}) and the exit status that
// run_reader_child reads: 0 read, 2 refused, 3 out of memory.
int reader_main(const std::filesystem::path& dir, const std::function<void()>& read);

// The child's side: reads DIR/request.json ({"name", "format",
// "max_unpacked_bytes"}) and DIR/upload, writes DIR/result.json (the fields
// of UploadRead, "textures" a count) with DIR/mesh (unpacked_mesh, when
// there is one) and DIR/texture-K, or DIR/error.json ({"error": kind,
// "detail"}) on an error of the file.  Returns the exit status: 0 read, 2
// refused (error.json says why), 3 out of memory.
int read_upload_main(const std::filesystem::path& dir);

}  // namespace cgview::server
