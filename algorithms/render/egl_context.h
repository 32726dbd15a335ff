// An OpenGL 3.3 (or later) core context with no window and no X server, through EGL.
//
// Platform selection (docs/DESIGN.md, "Headless rendering"): with
// GlPlatform::automatic, the EGL devices are enumerated
// (EGL_EXT_device_enumeration) and tried hardware first; then Mesa's
// surfaceless platform (llvmpipe); then software EGL devices.  The first that
// initialises, gives a 3.3 core context and makes it current wins; the
// reasons the others failed are kept in EglInfo::attempts.  The setting
// (GlPlatform, or the environment variable CGVIEW_GL_PLATFORM=auto|device|
// surfaceless when the option is automatic) restricts the candidates.
//
// EGL and GL headers stay in the .cpp: this header is plain C++.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace cgview::render {

enum class GlPlatform { automatic, device, surfaceless };

// "auto", "device", "surfaceless"; throws InvalidInput naming `what` otherwise.
GlPlatform parse_gl_platform(const std::string& text, const char* what = "gl platform");
const char* to_string(GlPlatform p);

struct EglInfo {
  std::string platform;  // "device 0", "surfaceless"
  std::string gl_vendor, gl_renderer, gl_version;
  bool software = false;              // llvmpipe, softpipe, SwiftShader, or an EGL_MESA_device_software device
  bool compute = false;               // OpenGL 4.3's compute shaders (the context is 4.3 or later)
  std::vector<std::string> attempts;  // "device 1 (NVIDIA): eglInitialize failed", ... in order tried
};

// Where library messages go (library code never prints).  The CLI and the
// server install one that prints; the default drops them.  The "software
// renderer only" message is sent once per process.
using RenderLog = std::function<void(const std::string& message)>;
void set_render_log(RenderLog log);

// For tests of the fallback: a candidate ("device 0", "surfaceless") for
// which `fail` returns true is abandoned after its context started, as if its
// driver had failed there.  nullptr (the default) turns it off.
void set_egl_fault_injection(std::function<bool(const std::string& candidate)> fail);

// Whether EGL lists a device that is not software (EGL_EXT_device_enumeration,
// without EGL_MESA_device_software), and the setting (as EglContext's, with
// CGVIEW_GL_PLATFORM) lets contexts start on devices: a cheap test, no
// context started, of whether a context may run on a GPU.
bool hardware_device_listed(GlPlatform platform = GlPlatform::automatic);

struct GlFunctions;         // the GL entry points, loaded through eglGetProcAddress (egl_context.cpp)
struct GlComputeFunctions;  // GL 4.3's compute entry points (gl_functions.h)

// One EGL display and context.  A context is current on one thread at a
// time: call make_current() on the thread that renders (Renderer does).
// The core profile version a context asks for: the renderer's 3.3, or 4.3
// for compute shaders (rays/gpu_ray_caster.h).  Drivers may give a newer
// one (Mesa does) or exactly this (NVIDIA does).
struct GlVersion {
  int major = 3, minor = 3;
};

class EglContext {
 public:
  explicit EglContext(GlPlatform platform = GlPlatform::automatic, GlVersion version = {});
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Binds the context to the calling thread (no surface).  Throws Error.
  void make_current();
  // Unbinds it from the calling thread.
  void release();

  const EglInfo& info() const;
  const GlFunctions& gl() const;
  // Null where the context has no compute shaders (info().compute false).
  const GlComputeFunctions* gl_compute() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cgview::render
