// A shared library opened where it is first needed rather than linked:
// linked, its eager binding (-z now) costs every start of every program
// that links it, a job's worker for each job included, for the few jobs
// that use it.  Never closed: the functions found in it, and what its
// static constructors registered (a plugin's algorithms), live as long as
// the program.  RTLD_NOW: a missing symbol is said when it is opened, not
// when a function is first called; RTLD_LOCAL: two libraries' own symbols
// never meet.
#pragma once

#include <string>

namespace cgview {

class SharedLibrary {
 public:
  // A name (a C string: a soname stays whole in the binary, where
  // bench/gpu_sdf.sh finds the libraries to carry) or a path.
  explicit SharedLibrary(const char* path);
  // Whether it opened; where not, why() says so, in the loader's words
  // (which name the library).
  bool opened() const { return handle_ != nullptr; }
  // Its function of that name, or null where it has none (or did not
  // open), and then why() names it.
  template <class F>
  F function(const char* name) {
    return reinterpret_cast<F>(symbol(name));
  }
  const std::string& why() const { return why_; }

 private:
  void* symbol(const char* name);
  void* handle_ = nullptr;
  std::string path_, why_;
};

}  // namespace cgview
