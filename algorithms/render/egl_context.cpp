#include "render/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>

#include "core/errors.h"
#include "core/shared_library.h"
#include "render/gl_functions.h"

namespace cgview::render {

namespace {

// libEGL, opened by the first render rather than bound at every start of
// each program that can render: a job's worker starts for every job, and
// most jobs never render (libEGL and libGLdispatch were ~0.2 ms of each
// start).  Only the functions below are called directly; the rest come
// from eglGetProcAddress as before.
#define CGVIEW_EGL_FUNCTIONS(X)                        \
  X(PFNEGLBINDAPIPROC, eglBindAPI)                     \
  X(PFNEGLCHOOSECONFIGPROC, eglChooseConfig)           \
  X(PFNEGLCREATECONTEXTPROC, eglCreateContext)         \
  X(PFNEGLDESTROYCONTEXTPROC, eglDestroyContext)       \
  X(PFNEGLGETCURRENTCONTEXTPROC, eglGetCurrentContext) \
  X(PFNEGLGETERRORPROC, eglGetError)                   \
  X(PFNEGLGETPROCADDRESSPROC, eglGetProcAddress)       \
  X(PFNEGLINITIALIZEPROC, eglInitialize)               \
  X(PFNEGLMAKECURRENTPROC, eglMakeCurrent)             \
  X(PFNEGLQUERYSTRINGPROC, eglQueryString)             \
  X(PFNEGLTERMINATEPROC, eglTerminate)

struct Egl {
#define CGVIEW_EGL_MEMBER(type, name) type name = nullptr;
  CGVIEW_EGL_FUNCTIONS(CGVIEW_EGL_MEMBER)
#undef CGVIEW_EGL_MEMBER
  std::string why_not;  // "" once every function was found
};

// The library's functions, looked up once (never closed: contexts outlive
// any one caller).  Throws Error where libEGL cannot be opened.
const Egl& egl() {
  static const Egl loaded = [] {
    Egl e;
    SharedLibrary lib("libEGL.so.1");
#define CGVIEW_EGL_FIND(type, name) e.name = lib.function<type>(#name);
    CGVIEW_EGL_FUNCTIONS(CGVIEW_EGL_FIND)
#undef CGVIEW_EGL_FIND
    if (!lib.why().empty()) e.why_not = "render: " + lib.why();
    return e;
  }();
  if (!loaded.why_not.empty()) throw Error(loaded.why_not);
  return loaded;
}

std::mutex g_mutex;  // guards the log and the display reference counts
RenderLog g_log;
std::function<bool(const std::string&)> g_fault;
std::atomic<bool> g_software_logged{false};
std::map<EGLDisplay, int> g_display_users;

void log_message(const std::string& m) {
  RenderLog log;
  {
    std::lock_guard lock(g_mutex);
    log = g_log;
  }
  if (log) log(m);
}

std::string egl_error() {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04X", unsigned(egl().eglGetError()));
  return buf;
}

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

bool is_software_renderer(const std::string& r) {
  return r.find("llvmpipe") != std::string::npos || r.find("softpipe") != std::string::npos ||
         r.find("SwiftShader") != std::string::npos || r.find("swrast") != std::string::npos;
}

struct Candidate {
  std::string name;
  EGLenum platform;
  void* native;
  bool software;
};

// The EGL devices (EGL_EXT_device_enumeration), in EGL's order.
std::vector<Candidate> device_candidates(const char* client) {
  std::vector<Candidate> out;
  if (!has_extension(client, "EGL_EXT_platform_device")) return out;
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(egl().eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(egl().eglGetProcAddress("eglQueryDeviceStringEXT"));
  EGLint n = 0;
  if (!query_devices || !query_devices(0, nullptr, &n) || n <= 0) return out;
  std::vector<EGLDeviceEXT> devices(n);
  query_devices(n, devices.data(), &n);
  for (EGLint i = 0; i < n; ++i) {
    const char* ext = query_string ? query_string(devices[i], EGL_EXTENSIONS) : nullptr;
    out.push_back({"device " + std::to_string(i), EGL_PLATFORM_DEVICE_EXT, devices[i],
                   has_extension(ext, "EGL_MESA_device_software")});
  }
  return out;
}

// The setting, with CGVIEW_GL_PLATFORM where it is automatic.
GlPlatform setting(GlPlatform platform) {
  if (platform == GlPlatform::automatic)
    if (const char* env = std::getenv("CGVIEW_GL_PLATFORM"); env && *env)
      return parse_gl_platform(env, "CGVIEW_GL_PLATFORM");
  return platform;
}

}  // namespace

bool hardware_device_listed(GlPlatform platform) {
  if (setting(platform) == GlPlatform::surfaceless) return false;
  try {
    egl();
  } catch (const Error&) {
    return false;  // no libEGL: no device either
  }
  for (const Candidate& c : device_candidates(egl().eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS)))
    if (!c.software) return true;
  return false;
}

GlPlatform parse_gl_platform(const std::string& text, const char* what) {
  if (text == "auto" || text == "automatic") return GlPlatform::automatic;
  if (text == "device") return GlPlatform::device;
  if (text == "surfaceless") return GlPlatform::surfaceless;
  throw InvalidInput(std::string(what) + ": unknown platform '" + text + "' (auto, device or surfaceless)");
}

const char* to_string(GlPlatform p) {
  switch (p) {
    case GlPlatform::automatic:
      return "auto";
    case GlPlatform::device:
      return "device";
    case GlPlatform::surfaceless:
      return "surfaceless";
  }
  return "auto";
}

void set_egl_fault_injection(std::function<bool(const std::string&)> fail) {
  std::lock_guard lock(g_mutex);
  g_fault = std::move(fail);
}

void set_render_log(RenderLog log) {
  std::lock_guard lock(g_mutex);
  g_log = std::move(log);
}

struct EglContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EglInfo info;
  GlFunctions gl;
  GlComputeFunctions compute;

  // Tries one candidate; on failure returns the reason and leaves nothing behind.
  std::string try_start(const Candidate& c, PFNEGLGETPLATFORMDISPLAYEXTPROC get_display, GlVersion version) {
    EGLDisplay d = get_display(c.platform, c.native, nullptr);
    if (d == EGL_NO_DISPLAY) return "no display (" + egl_error() + ")";
    EGLint major = 0, minor = 0;
    if (!egl().eglInitialize(d, &major, &minor)) return "eglInitialize failed (" + egl_error() + ")";
    {
      std::lock_guard lock(g_mutex);
      ++g_display_users[d];
    }
    display = d;
    auto fail = [&](std::string why) {
      if (context != EGL_NO_CONTEXT) {
        egl().eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        egl().eglDestroyContext(display, context);
      }
      context = EGL_NO_CONTEXT;
      drop_display();
      return why;
    };
    if (!has_extension(egl().eglQueryString(d, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context"))
      return fail("no EGL_KHR_surfaceless_context");
    if (!egl().eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(OpenGL) failed (" + egl_error() + ")");
    EGLConfig config = nullptr;
    EGLint count = 0;
    for (EGLint surface : {EGLint(EGL_PBUFFER_BIT), EGLint(0)}) {
      const EGLint attrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, surface, EGL_NONE};
      if (egl().eglChooseConfig(d, attrs, &config, 1, &count) && count > 0) break;
    }
    if (count <= 0) return fail("no OpenGL config");
    const EGLint ctx_attrs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                EGLint(version.major),
                                EGL_CONTEXT_MINOR_VERSION,
                                EGLint(version.minor),
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                EGL_NONE};
    context = egl().eglCreateContext(d, config, EGL_NO_CONTEXT, ctx_attrs);
    if (context == EGL_NO_CONTEXT)
      return fail("no OpenGL " + std::to_string(version.major) + "." + std::to_string(version.minor) +
                  " core context (" + egl_error() + ")");
    if (!egl().eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
      return fail("eglMakeCurrent failed (" + egl_error() + ")");
#define CGVIEW_GL_LOAD(type, name) gl.name = reinterpret_cast<type>(egl().eglGetProcAddress(#name));
    CGVIEW_GL_FUNCTIONS(CGVIEW_GL_LOAD)
#undef CGVIEW_GL_LOAD
#define CGVIEW_GL_CHECK(type, name) \
  if (!gl.name) return fail("no " #name);
    CGVIEW_GL_FUNCTIONS(CGVIEW_GL_CHECK)
#undef CGVIEW_GL_CHECK
    auto str = [&](GLenum e) {
      const GLubyte* s = gl.glGetString(e);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    info.gl_vendor = str(GL_VENDOR);
    info.gl_renderer = str(GL_RENDERER);
    info.gl_version = str(GL_VERSION);
    if (info.gl_renderer.empty()) return fail("glGetString(GL_RENDERER) gave nothing");
    {
      std::function<bool(const std::string&)> fault;
      {
        std::lock_guard lock(g_mutex);
        fault = g_fault;
      }
      if (fault && fault(c.name)) return fail("refused by fault injection");
    }
    info.platform = c.name;
    info.software = c.software || is_software_renderer(info.gl_renderer);
    // Compute shaders where the context is 4.3 or later (asked for, or given
    // by a driver that gives its newest core version).
    GLint gl_major = 0, gl_minor = 0;
    gl.glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
    gl.glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
#define CGVIEW_GL_LOAD(type, name) compute.name = reinterpret_cast<type>(egl().eglGetProcAddress(#name));
    CGVIEW_GL_COMPUTE_FUNCTIONS(CGVIEW_GL_LOAD)
#undef CGVIEW_GL_LOAD
    info.compute = gl_major * 10 + gl_minor >= 43;
#define CGVIEW_GL_CHECK(type, name) info.compute = info.compute && compute.name;
    CGVIEW_GL_COMPUTE_FUNCTIONS(CGVIEW_GL_CHECK)
#undef CGVIEW_GL_CHECK
    egl().eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    return {};
  }

  void drop_display() {
    if (display == EGL_NO_DISPLAY) return;
    bool last = false;
    {
      std::lock_guard lock(g_mutex);
      last = --g_display_users[display] == 0;
      if (last) g_display_users.erase(display);
    }
    // Displays are shared by every context on the same device: terminate
    // only when the last one goes.
    if (last) egl().eglTerminate(display);
    display = EGL_NO_DISPLAY;
  }
};

EglContext::EglContext(GlPlatform platform, GlVersion version) : impl_(std::make_unique<Impl>()) {
  platform = setting(platform);
  const char* client = egl().eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(egl().eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!client || !get_display)
    throw Error("render: EGL has no client extensions or no eglGetPlatformDisplayEXT: cannot render without a window");

  std::vector<Candidate> hardware, software_devices, surfaceless;
  if (platform != GlPlatform::surfaceless)
    for (const Candidate& c : device_candidates(client)) (c.software ? software_devices : hardware).push_back(c);
  if (platform != GlPlatform::device && has_extension(client, "EGL_MESA_platform_surfaceless"))
    surfaceless.push_back({"surfaceless", EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, true});

  std::vector<Candidate> order = hardware;
  order.insert(order.end(), surfaceless.begin(), surfaceless.end());
  order.insert(order.end(), software_devices.begin(), software_devices.end());

  std::string reasons;
  for (const Candidate& c : order) {
    const std::string why = impl_->try_start(c, get_display, version);
    if (why.empty()) break;
    impl_->info.attempts.push_back(c.name + ": " + why);
    reasons += (reasons.empty() ? "" : "; ") + c.name + ": " + why;
  }
  if (impl_->context == EGL_NO_CONTEXT)
    throw Error("render: no EGL platform could start an OpenGL " + std::to_string(version.major) + "." +
                std::to_string(version.minor) + " core context (setting: " + to_string(platform) + ")" +
                (reasons.empty() ? ": none available" : ": " + reasons));
  impl_->info.attempts.push_back(impl_->info.platform + ": started");

  if (impl_->info.software && !g_software_logged.exchange(true))
    log_message("render: software renderer only (" + impl_->info.gl_renderer + " on the " + impl_->info.platform +
                " platform" + (hardware.empty() ? ", no GPU EGL device found" : ", the GPU devices failed to start") +
                "): renders are slower");
}

EglContext::~EglContext() {
  if (impl_->context != EGL_NO_CONTEXT) {
    if (egl().eglGetCurrentContext() == impl_->context)
      egl().eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    egl().eglDestroyContext(impl_->display, impl_->context);
  }
  impl_->drop_display();
}

void EglContext::make_current() {
  if (egl().eglGetCurrentContext() == impl_->context) return;
  // The bound API is per thread, and eglMakeCurrent uses it.
  egl().eglBindAPI(EGL_OPENGL_API);
  if (!egl().eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw Error("render: eglMakeCurrent failed (" + egl_error() + "): is the context current on another thread?");
}

void EglContext::release() {
  if (egl().eglGetCurrentContext() == impl_->context)
    egl().eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

const EglInfo& EglContext::info() const { return impl_->info; }
const GlFunctions& EglContext::gl() const { return impl_->gl; }
const GlComputeFunctions* EglContext::gl_compute() const { return impl_->info.compute ? &impl_->compute : nullptr; }

}  // namespace cgview::render
