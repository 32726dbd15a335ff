#include "core/shared_library.h"

#include <dlfcn.h>

namespace cgview {
namespace {

// The loader's own words (they name the library), else ours.
std::string said_by_loader(const std::string& otherwise) {
  const char* e = ::dlerror();
  return e ? e : otherwise;
}

}  // namespace

SharedLibrary::SharedLibrary(const char* path) : path_(path) {
  handle_ = ::dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!handle_) why_ = said_by_loader(path);
}

void* SharedLibrary::symbol(const char* name) {
  if (!handle_) return nullptr;
  void* f = ::dlsym(handle_, name);
  if (!f && why_.empty()) why_ = said_by_loader(path_ + ": no " + name);
  return f;
}

}  // namespace cgview
