#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

#include "core/errors.h"
#include "render/gl_functions.h"

namespace cgview::render {

namespace {

const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_scalar;
uniform mat4 u_mvp;
uniform mat4 u_mv;
out vec3 v_view_pos;
out vec3 v_normal;
out float v_scalar;
void main() {
  v_view_pos = (u_mv * vec4(a_pos, 1.0)).xyz;
  v_normal = mat3(u_mv) * a_normal;
  v_scalar = a_scalar;
  gl_Position = u_mvp * vec4(a_pos, 1.0);
}
)";

// Modes: 0 points, 1 wireframe, 2 flat, 3 smooth, 4 toon.  Fields: 0 none,
// 1 per vertex, 2 per face (a texture buffer indexed by gl_PrimitiveID).
// Colour maps: 0 viridis, 1 blue-white-red, 2 categorical.
const char* kMeshFragment = R"(#version 330 core
in vec3 v_view_pos;
in vec3 v_normal;
in float v_scalar;
uniform int u_mode;
uniform int u_field;
uniform int u_map;
uniform bool u_ortho;
uniform vec4 u_color;
uniform uint u_face_base;
uniform samplerBuffer u_face_values;
layout(location = 0) out vec4 o_color;
layout(location = 1) out uint o_face;

vec3 viridis(float t) {
  const vec3 c0 = vec3(0.2777273272234177, 0.005407344544966578, 0.3340998053353061);
  const vec3 c1 = vec3(0.1050930431085774, 1.404613529898575, 1.384590162594685);
  const vec3 c2 = vec3(-0.3308618287255563, 0.214847559468213, 0.09509516302823659);
  const vec3 c3 = vec3(-4.634230498983486, -5.799100973351585, -19.33244095627987);
  const vec3 c4 = vec3(6.228269936347081, 14.17993336680509, 56.69055260068105);
  const vec3 c5 = vec3(4.776384997670288, -13.74514537774601, -65.35303263337234);
  const vec3 c6 = vec3(-5.435455855934631, 4.645852612178535, 26.3124352495832);
  t = clamp(t, 0.0, 1.0);
  return clamp(c0 + t * (c1 + t * (c2 + t * (c3 + t * (c4 + t * (c5 + t * c6))))), 0.0, 1.0);
}
vec3 hsv(float h, float s, float v) {
  vec3 k = clamp(abs(mod(h * 6.0 + vec3(0.0, 4.0, 2.0), 6.0) - 3.0) - 1.0, 0.0, 1.0);
  return v * mix(vec3(1.0), k, s);
}
vec3 colormap(float s) {
  if (u_map == 1) {
    vec3 blue = vec3(0.23, 0.30, 0.75), white = vec3(0.87), red = vec3(0.71, 0.02, 0.15);
    return s < 0.5 ? mix(blue, white, clamp(2.0 * s, 0.0, 1.0)) : mix(white, red, clamp(2.0 * s - 1.0, 0.0, 1.0));
  }
  if (u_map == 2) return hsv(fract(floor(s + 0.5) * 0.61803398875), 0.65, 0.9);
  return viridis(s);
}
void main() {
  float s = u_field == 2 ? texelFetch(u_face_values, gl_PrimitiveID).r : v_scalar;
  vec3 base = u_field == 0 ? u_color.rgb : colormap(s);
  vec3 c;
  if (u_mode <= 1) {
    c = u_field == 0 ? base * 0.25 : base;
  } else {
    vec3 n = u_mode == 2 ? cross(dFdx(v_view_pos), dFdy(v_view_pos)) : v_normal;
    n = length(n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    vec3 v = u_ortho ? vec3(0.0, 0.0, 1.0) : normalize(-v_view_pos);
    if (dot(n, v) < 0.0) n = -n;
    float d = max(dot(n, v), 0.0);
    if (u_mode == 4) {
      float q = d > 0.8 ? 1.0 : (d > 0.45 ? 0.72 : (d > 0.2 ? 0.48 : 0.3));
      c = d < 0.12 ? vec3(0.08) : base * q;
    } else {
      c = base * (0.22 + 0.78 * d) + vec3(0.12) * pow(d, 48.0);
    }
  }
  o_color = vec4(clamp(c, 0.0, 1.0), 1.0);
  o_face = u_face_base + uint(gl_PrimitiveID);
}
)";

// Views for algorithms: depth and face ids only, the cheapest fragment work.
const char* kCaptureFragment = R"(#version 330 core
layout(location = 1) out uint o_face;
void main() { o_face = uint(gl_PrimitiveID); }
)";

const char* kDepthFragment = R"(#version 330 core
void main() {}
)";

// Both depths at once (capture's back_depth): every fragment, no depth test,
// blended by MIN into (z, -z), so a pixel keeps the nearest z and minus the
// farthest.
const char* kRangeFragment = R"(#version 330 core
layout(location = 2) out vec2 o_range;
void main() { o_range = vec2(gl_FragCoord.z, -gl_FragCoord.z); }
)";

const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
uniform mat4 u_mvp;
void main() { gl_Position = u_mvp * vec4(a_pos, 1.0); }
)";

const char* kLineFragment = R"(#version 330 core
uniform vec4 u_color;
layout(location = 0) out vec4 o_color;
void main() { o_color = u_color; }
)";

std::array<float, 16> to_float(const Mat4& m) {
  std::array<float, 16> f;
  for (int i = 0; i < 16; ++i) f[i] = float(m.m[i]);
  return f;
}

BBox bounding_box_of(const std::vector<RenderItem>& items) {
  BBox box;
  for (const RenderItem& it : items) {
    const BBox b = bounding_box(*it.mesh);
    if (!b.empty()) {
      box.add(b.min);
      box.add(b.max);
    }
  }
  return box;
}

// Values as the shader's colour map wants them: [0, 1] for sequential maps,
// 0.5 + v / (2 max|v|) for symmetric ones, the labels themselves for categorical ones.
std::vector<float> shader_values(const ScalarField& f, int& map) {
  if (f.hint == ColorHint::categorical) {
    map = 2;
    return f.values;
  }
  if (f.hint == ColorHint::symmetric) {
    map = 1;
    float m = 0;
    for (float v : f.values)
      if (std::isfinite(v)) m = std::max(m, std::abs(v));
    std::vector<float> out(f.values.size(), 0.5f);
    if (m > 0)
      for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = std::isfinite(f.values[i]) ? 0.5f + 0.5f * f.values[i] / m : 0.5f;
    return out;
  }
  map = 0;
  return f.normalized();
}

}  // namespace

RenderMode parse_render_mode(const std::string& text, const char* what) {
  if (text == "points") return RenderMode::points;
  if (text == "wireframe") return RenderMode::wireframe;
  if (text == "flat") return RenderMode::flat;
  if (text == "smooth") return RenderMode::smooth;
  if (text == "toon") return RenderMode::toon;
  throw InvalidInput(std::string(what) + ": unknown mode '" + text + "' (points, wireframe, flat, smooth or toon)");
}

const char* to_string(RenderMode m) {
  switch (m) {
    case RenderMode::points:
      return "points";
    case RenderMode::wireframe:
      return "wireframe";
    case RenderMode::flat:
      return "flat";
    case RenderMode::smooth:
      return "smooth";
    case RenderMode::toon:
      return "toon";
  }
  return "smooth";
}

void check_image_size(int width, int height) {
  if (width < 1 || width > kMaxImageSize)
    throw InvalidInput("width must be in [1, " + std::to_string(kMaxImageSize) + "], got " + std::to_string(width));
  if (height < 1 || height > kMaxImageSize)
    throw InvalidInput("height must be in [1, " + std::to_string(kMaxImageSize) + "], got " + std::to_string(height));
}

struct Renderer::Impl {
  EglContext context;
  const GlFunctions& gl;
  GLuint mesh_program = 0, line_program = 0, capture_program = 0, depth_program = 0, range_program = 0;
  GLuint fbo = 0, rb_color = 0, rb_face = 0, rb_depth = 0;
  GLuint rb_range = 0;  // RG32F, attached (as colour 2) only when a capture asks for back depth
  int fbo_w = 0, fbo_h = 0;
  GlObjectCounts counts;
  std::set<GLuint> ever_buffers, ever_arrays, ever_textures, ever_fbos, ever_rbs, ever_programs;

  explicit Impl(GlPlatform p) : context(p), gl(context.gl()) {}

  // Makes the context current for the lifetime of a call, and releases it.
  struct Current {
    EglContext& c;
    explicit Current(EglContext& ctx) : c(ctx) { c.make_current(); }
    ~Current() { c.release(); }
  };

  GLuint gen_buffer() {
    GLuint b = 0;
    gl.glGenBuffers(1, &b);
    ++counts.buffers;
    ever_buffers.insert(b);
    return b;
  }
  void delete_buffer(GLuint& b) {
    if (!b) return;
    gl.glDeleteBuffers(1, &b);
    --counts.buffers;
    b = 0;
  }
  GLuint gen_array() {
    GLuint a = 0;
    gl.glGenVertexArrays(1, &a);
    ++counts.vertex_arrays;
    ever_arrays.insert(a);
    return a;
  }
  void delete_array(GLuint& a) {
    if (!a) return;
    gl.glDeleteVertexArrays(1, &a);
    --counts.vertex_arrays;
    a = 0;
  }
  GLuint gen_texture() {
    GLuint t = 0;
    gl.glGenTextures(1, &t);
    ++counts.textures;
    ever_textures.insert(t);
    return t;
  }
  void delete_texture(GLuint& t) {
    if (!t) return;
    gl.glDeleteTextures(1, &t);
    --counts.textures;
    t = 0;
  }
  GLuint gen_renderbuffer() {
    GLuint r = 0;
    gl.glGenRenderbuffers(1, &r);
    ++counts.renderbuffers;
    ever_rbs.insert(r);
    return r;
  }
  void delete_renderbuffer(GLuint& r) {
    if (!r) return;
    gl.glDeleteRenderbuffers(1, &r);
    --counts.renderbuffers;
    r = 0;
  }

  GLuint link(const char* vs, const char* fs) {
    const GLuint p = link_program(gl, {{GL_VERTEX_SHADER, vs}, {GL_FRAGMENT_SHADER, fs}}, "render");
    ++counts.programs;
    ever_programs.insert(p);
    return p;
  }

  void setup() {
    Current cur(context);
    mesh_program = link(kMeshVertex, kMeshFragment);
    line_program = link(kLineVertex, kLineFragment);
    capture_program = link(kLineVertex, kCaptureFragment);
    depth_program = link(kLineVertex, kDepthFragment);
    range_program = link(kLineVertex, kRangeFragment);
  }

  void teardown() {
    Current cur(context);
    free_framebuffer();
    if (mesh_program) gl.glDeleteProgram(mesh_program), --counts.programs;
    if (line_program) gl.glDeleteProgram(line_program), --counts.programs;
    if (capture_program) gl.glDeleteProgram(capture_program), --counts.programs;
    if (depth_program) gl.glDeleteProgram(depth_program), --counts.programs;
    if (range_program) gl.glDeleteProgram(range_program), --counts.programs;
    mesh_program = line_program = capture_program = depth_program = range_program = 0;
  }

  void free_framebuffer() {
    if (fbo) {
      gl.glDeleteFramebuffers(1, &fbo);
      --counts.framebuffers;
      fbo = 0;
    }
    delete_renderbuffer(rb_color);
    delete_renderbuffer(rb_face);
    delete_renderbuffer(rb_depth);
    delete_renderbuffer(rb_range);
    fbo_w = fbo_h = 0;
  }

  void ensure_framebuffer(int w, int h) {
    if (fbo && fbo_w == w && fbo_h == h) return;
    free_framebuffer();
    gl.glGenFramebuffers(1, &fbo);
    ++counts.framebuffers;
    ever_fbos.insert(fbo);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    attach(rb_color, GL_RGBA8, GL_COLOR_ATTACHMENT0, w, h);
    attach(rb_face, GL_R32UI, GL_COLOR_ATTACHMENT1, w, h);
    attach(rb_depth, GL_DEPTH_COMPONENT32F, GL_DEPTH_ATTACHMENT, w, h);
    check_framebuffer(w, h);
    fbo_w = w;
    fbo_h = h;
  }

  // The bound framebuffer's RG32F attachment for both depths, made the first
  // time a capture asks for them at this size.
  void ensure_range_buffer() {
    if (rb_range) return;
    attach(rb_range, GL_RG32F, GL_COLOR_ATTACHMENT2, fbo_w, fbo_h);
    check_framebuffer(fbo_w, fbo_h);
  }

  // Blending back to its defaults after a capture with back depth (the
  // depth test is set by bind_target for every draw).
  void end_range() {
    gl.glDisable(GL_BLEND);
    gl.glBlendEquation(GL_FUNC_ADD);
  }

  void attach(GLuint& rb, GLenum format, GLenum point, int w, int h) {
    rb = gen_renderbuffer();
    gl.glBindRenderbuffer(GL_RENDERBUFFER, rb);
    gl.glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
    gl.glFramebufferRenderbuffer(GL_FRAMEBUFFER, point, GL_RENDERBUFFER, rb);
  }

  void check_framebuffer(int w, int h) {
    const GLenum status = gl.glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      free_framebuffer();
      throw Error("render: the framebuffer of " + std::to_string(w) + "x" + std::to_string(h) +
                  " is incomplete (GL status " + std::to_string(status) + ")");
    }
  }

  // A mesh's buffers on the GPU: positions relative to `origin` (floats keep
  // their precision near the object), optional normals and scalars.
  struct GpuMesh {
    GLuint vao = 0, pos = 0, normal = 0, scalar = 0, index = 0, face_buffer = 0, face_texture = 0;
    GLsizei index_count = 0, vertex_count = 0;
    int field = 0, map = 0;
  };

  GpuMesh upload(const Mesh& mesh, Vec3 origin, bool normals, const ScalarField* field) {
    GpuMesh g;
    g.vertex_count = GLsizei(mesh.positions.size());
    g.vao = gen_array();
    gl.glBindVertexArray(g.vao);
    std::vector<float> buf(mesh.positions.size() * 3);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3 p = mesh.positions[i] - origin;
      buf[3 * i] = float(p.x);
      buf[3 * i + 1] = float(p.y);
      buf[3 * i + 2] = float(p.z);
    }
    g.pos = gen_buffer();
    gl.glBindBuffer(GL_ARRAY_BUFFER, g.pos);
    gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(buf.size() * sizeof(float)), buf.data(), GL_STATIC_DRAW);
    gl.glEnableVertexAttribArray(0);
    gl.glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    if (normals && !mesh.faces.empty()) {
      if (mesh.has_normals() && mesh.attributes_per_vertex() && mesh.normals.size() == mesh.positions.size()) {
        for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
          buf[3 * i] = mesh.normals[i].x;
          buf[3 * i + 1] = mesh.normals[i].y;
          buf[3 * i + 2] = mesh.normals[i].z;
        }
      } else {
        const std::vector<Vec3> n = vertex_normals(mesh);
        for (std::size_t i = 0; i < n.size(); ++i) {
          buf[3 * i] = float(n[i].x);
          buf[3 * i + 1] = float(n[i].y);
          buf[3 * i + 2] = float(n[i].z);
        }
      }
      g.normal = gen_buffer();
      gl.glBindBuffer(GL_ARRAY_BUFFER, g.normal);
      gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(buf.size() * sizeof(float)), buf.data(), GL_STATIC_DRAW);
      gl.glEnableVertexAttribArray(1);
      gl.glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    } else {
      gl.glDisableVertexAttribArray(1);
      gl.glVertexAttrib3f(1, 0, 0, 1);
    }
    gl.glDisableVertexAttribArray(2);
    gl.glVertexAttrib1f(2, 0);
    if (field) {
      const std::vector<float> values = shader_values(*field, g.map);
      if (field->location == Location::vertex) {
        g.field = 1;
        g.scalar = gen_buffer();
        gl.glBindBuffer(GL_ARRAY_BUFFER, g.scalar);
        gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(values.size() * sizeof(float)), values.data(), GL_STATIC_DRAW);
        gl.glEnableVertexAttribArray(2);
        gl.glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
      } else {
        g.field = 2;
        g.face_buffer = gen_buffer();
        gl.glBindBuffer(GL_TEXTURE_BUFFER, g.face_buffer);
        gl.glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(values.size() * sizeof(float)), values.data(), GL_STATIC_DRAW);
        g.face_texture = gen_texture();
        gl.glBindTexture(GL_TEXTURE_BUFFER, g.face_texture);
        gl.glTexBuffer(GL_TEXTURE_BUFFER, GL_R32F, g.face_buffer);
        gl.glBindTexture(GL_TEXTURE_BUFFER, 0);
        gl.glBindBuffer(GL_TEXTURE_BUFFER, 0);
      }
    }
    static_assert(sizeof(Tri) == 3 * sizeof(GLuint));
    if (mesh.faces.empty()) {
      gl.glBindVertexArray(0);
      gl.glBindBuffer(GL_ARRAY_BUFFER, 0);
      return g;
    }
    g.index = gen_buffer();
    gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.index);
    gl.glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.faces.size() * sizeof(Tri)), mesh.faces.data(),
                    GL_STATIC_DRAW);
    g.index_count = GLsizei(mesh.faces.size() * 3);
    gl.glBindVertexArray(0);
    gl.glBindBuffer(GL_ARRAY_BUFFER, 0);
    return g;
  }

  void release_mesh(GpuMesh& g) {
    delete_array(g.vao);
    delete_buffer(g.pos);
    delete_buffer(g.normal);
    delete_buffer(g.scalar);
    delete_buffer(g.index);
    delete_buffer(g.face_buffer);
    delete_texture(g.face_texture);
  }

  GLint loc(GLuint program, const char* name) { return gl.glGetUniformLocation(program, name); }

  void draw_mesh(const GpuMesh& g, const Mat4& view, const Mat4& proj, Vec3 origin, RenderMode mode, bool ortho,
                 Color color, std::uint32_t face_base) {
    const Mat4 mv = view * translation(origin), mvp = proj * mv;
    gl.glUseProgram(mesh_program);
    gl.glUniformMatrix4fv(loc(mesh_program, "u_mvp"), 1, GL_FALSE, to_float(mvp).data());
    gl.glUniformMatrix4fv(loc(mesh_program, "u_mv"), 1, GL_FALSE, to_float(mv).data());
    // A mesh with no faces (a point cloud) is drawn as its points, whatever the mode.
    const bool cloud = g.index_count == 0;
    if (cloud) mode = RenderMode::points;
    gl.glUniform1i(loc(mesh_program, "u_mode"), int(mode));
    gl.glUniform1i(loc(mesh_program, "u_field"), g.field);
    gl.glUniform1i(loc(mesh_program, "u_map"), g.map);
    gl.glUniform1i(loc(mesh_program, "u_ortho"), ortho ? 1 : 0);
    gl.glUniform4f(loc(mesh_program, "u_color"), color.r / 255.f, color.g / 255.f, color.b / 255.f, 1.f);
    gl.glUniform1ui(loc(mesh_program, "u_face_base"), face_base);
    gl.glUniform1i(loc(mesh_program, "u_face_values"), 0);
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glBindTexture(GL_TEXTURE_BUFFER, g.face_texture);
    const GLenum polygon = mode == RenderMode::points ? GL_POINT : (mode == RenderMode::wireframe ? GL_LINE : GL_FILL);
    gl.glPolygonMode(GL_FRONT_AND_BACK, polygon);
    gl.glBindVertexArray(g.vao);
    if (cloud) gl.glDrawArrays(GL_POINTS, 0, g.vertex_count);
    else gl.glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
    gl.glBindVertexArray(0);
    gl.glBindTexture(GL_TEXTURE_BUFFER, 0);
    gl.glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }

  void draw_skeleton(const Skeleton& s, const Mat4& view, const Mat4& proj, Vec3 origin) {
    if (s.nodes.empty()) return;
    std::vector<float> pos(s.nodes.size() * 3);
    for (std::size_t i = 0; i < s.nodes.size(); ++i) {
      const Vec3 p = s.nodes[i] - origin;
      pos[3 * i] = float(p.x), pos[3 * i + 1] = float(p.y), pos[3 * i + 2] = float(p.z);
    }
    GLuint vao = gen_array(), vbo = gen_buffer(), ebo = gen_buffer();
    gl.glBindVertexArray(vao);
    gl.glBindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(pos.size() * sizeof(float)), pos.data(), GL_STREAM_DRAW);
    gl.glEnableVertexAttribArray(0);
    gl.glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
    gl.glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(s.edges.size() * sizeof(s.edges[0])), s.edges.data(),
                    GL_STREAM_DRAW);
    gl.glUseProgram(line_program);
    const Mat4 mvp = proj * view * translation(origin);
    gl.glUniformMatrix4fv(loc(line_program, "u_mvp"), 1, GL_FALSE, to_float(mvp).data());
    // The overlay writes colour only: the face ids stay those of the surface.
    const GLenum only_color[2] = {GL_COLOR_ATTACHMENT0, GL_NONE};
    gl.glDrawBuffers(2, only_color);
    gl.glDisable(GL_DEPTH_TEST);
    gl.glUniform4f(loc(line_program, "u_color"), 0.9f, 0.15f, 0.1f, 1.f);
    gl.glDrawElements(GL_LINES, GLsizei(s.edges.size() * 2), GL_UNSIGNED_INT, nullptr);
    gl.glPointSize(5);
    gl.glUniform4f(loc(line_program, "u_color"), 0.55f, 0.05f, 0.05f, 1.f);
    gl.glDrawArrays(GL_POINTS, 0, GLsizei(s.nodes.size()));
    gl.glEnable(GL_DEPTH_TEST);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.glDrawBuffers(2, both);
    gl.glBindVertexArray(0);
    delete_array(vao);
    delete_buffer(vbo);
    delete_buffer(ebo);
  }

  // The w x h framebuffer bound, with the depth test every draw uses
  // (depth writes on before any clear: a depth clear obeys the mask).
  void bind_target(int w, int h) {
    ensure_framebuffer(w, h);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.glViewport(0, 0, w, h);
    gl.glEnable(GL_DEPTH_TEST);
    gl.glDepthFunc(GL_LESS);
    gl.glDepthMask(GL_TRUE);
    gl.glDisable(GL_CULL_FACE);
  }

  // Depth to the far plane; with `ids`, the face-id buffer to "no face".
  void clear_depth(bool ids) {
    const GLfloat far_depth = 1.0f;
    gl.glClearBufferfv(GL_DEPTH, 0, &far_depth);
    if (ids) {
      const GLuint none[4] = {kNoFace, 0, 0, 0};
      gl.glClearBufferuiv(GL_COLOR, 1, none);
    }
  }

  void begin_frame(int w, int h, Color bg) {
    bind_target(w, h);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl.glDrawBuffers(2, both);
    const GLfloat c[4] = {bg.r / 255.f, bg.g / 255.f, bg.b / 255.f, bg.a / 255.f};
    gl.glClearBufferfv(GL_COLOR, 0, c);
    clear_depth(true);
  }

  // Rows come from GL bottom first; flip them to the top-first order of images.
  template <class T>
  void flip_rows(std::vector<T>& v, int w, int h, int channels) {
    const std::size_t row = std::size_t(w) * channels;
    std::vector<T> tmp(row);
    for (int y = 0; y < h / 2; ++y) {
      T* a = v.data() + std::size_t(y) * row;
      T* b = v.data() + std::size_t(h - 1 - y) * row;
      std::memcpy(tmp.data(), a, row * sizeof(T));
      std::memcpy(a, b, row * sizeof(T));
      std::memcpy(b, tmp.data(), row * sizeof(T));
    }
  }

  std::vector<float> read_depth(int w, int h) {
    std::vector<float> d(std::size_t(w) * h);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, d.data());
    flip_rows(d, w, h, 1);
    return d;
  }
  // A colour attachment read back (`channels` values of T a pixel), rows
  // flipped to the top-first order.
  template <class T>
  std::vector<T> read_attachment(GLenum attachment, GLenum format, GLenum type, int channels, int w, int h) {
    std::vector<T> v(std::size_t(channels) * w * h);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.glReadBuffer(attachment);
    gl.glReadPixels(0, 0, w, h, format, type, v.data());
    gl.glReadBuffer(GL_COLOR_ATTACHMENT0);
    flip_rows(v, w, h, channels);
    return v;
  }
  // The range buffer: (nearest z, minus the farthest z) per pixel.
  std::vector<float> read_range(int w, int h) {
    return read_attachment<float>(GL_COLOR_ATTACHMENT2, GL_RG, GL_FLOAT, 2, w, h);
  }
  std::vector<std::uint32_t> read_ids(int w, int h) {
    return read_attachment<std::uint32_t>(GL_COLOR_ATTACHMENT1, GL_RED_INTEGER, GL_UNSIGNED_INT, 1, w, h);
  }
  Image read_color(int w, int h) {
    return Image{w, h, read_attachment<std::uint8_t>(GL_COLOR_ATTACHMENT0, GL_RGBA, GL_UNSIGNED_BYTE, 4, w, h)};
  }

  void check_errors(const char* where) {
    const GLenum e = gl.glGetError();
    if (e != GL_NO_ERROR) {
      while (gl.glGetError() != GL_NO_ERROR) {
      }
      throw Error(std::string("render: OpenGL error ") + std::to_string(e) + " in " + where);
    }
  }
};

Renderer::Renderer(GlPlatform platform) : impl_(std::make_unique<Impl>(platform)) { impl_->setup(); }

Renderer::~Renderer() {
  try {
    impl_->teardown();
  } catch (...) {
    // A context that cannot be made current any more: EGL frees its objects with it.
  }
}

const EglInfo& Renderer::info() const { return impl_->context.info(); }
GlObjectCounts Renderer::live_objects() const { return impl_->counts; }

GlObjectCounts Renderer::gl_objects_alive() {
  Impl::Current cur(impl_->context);
  const GlFunctions& gl = impl_->gl;
  GlObjectCounts c;
  for (GLuint id : impl_->ever_buffers) c.buffers += gl.glIsBuffer(id) ? 1 : 0;
  for (GLuint id : impl_->ever_arrays) c.vertex_arrays += gl.glIsVertexArray(id) ? 1 : 0;
  for (GLuint id : impl_->ever_textures) c.textures += gl.glIsTexture(id) ? 1 : 0;
  for (GLuint id : impl_->ever_fbos) c.framebuffers += gl.glIsFramebuffer(id) ? 1 : 0;
  for (GLuint id : impl_->ever_rbs) c.renderbuffers += gl.glIsRenderbuffer(id) ? 1 : 0;
  for (GLuint id : impl_->ever_programs) c.programs += gl.glIsProgram(id) ? 1 : 0;
  return c;
}

RenderResult Renderer::render(const std::vector<RenderItem>& items, const RenderParams& params) {
  check_image_size(params.width, params.height);
  if (items.empty()) throw InvalidInput("render: nothing to draw (no meshes)");
  for (std::size_t k = 0; k < items.size(); ++k) {
    const RenderItem& it = items[k];
    if (!it.mesh || it.mesh->positions.empty())
      throw InvalidInput("render: mesh " + std::to_string(k) + " has no vertices");
    it.mesh->validate();
    if (it.field) {
      try {
        it.field->check_matches(*it.mesh);
      } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("field: ") + e.what());
      }
    }
    if (it.skeleton) {
      try {
        it.skeleton->validate();
      } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("skeleton: ") + e.what());
      }
    }
  }
  const BBox box = bounding_box_of(items);
  RenderResult out;
  out.camera = resolve_camera(params.camera, box, params.width, params.height);
  const Vec3 origin = box.center();
  const bool ortho = out.camera.kind == Projection::orthographic;
  const bool normals = params.mode == RenderMode::smooth || params.mode == RenderMode::toon;

  Impl& im = *impl_;
  Impl::Current cur(im.context);
  im.begin_frame(params.width, params.height, params.background);
  im.gl.glPointSize(std::max(1.f, params.point_size));
  im.gl.glLineWidth(1.f);
  std::uint32_t face_base = 0;
  std::vector<Impl::GpuMesh> uploaded;
  try {
    for (const RenderItem& it : items) {
      uploaded.push_back(im.upload(*it.mesh, origin, normals, it.field));
      im.draw_mesh(uploaded.back(), out.camera.view, out.camera.projection, origin, params.mode, ortho, it.color,
                   face_base);
      face_base += std::uint32_t(it.mesh->faces.size());
    }
    for (const RenderItem& it : items)
      if (it.skeleton) im.draw_skeleton(*it.skeleton, out.camera.view, out.camera.projection, origin);
    im.check_errors("drawing");
    if (params.color) out.color = im.read_color(params.width, params.height);
    if (params.depth || params.silhouette) out.depth = im.read_depth(params.width, params.height);
    if (params.face_ids) out.face_ids = im.read_ids(params.width, params.height);
    im.check_errors("reading back");
  } catch (...) {
    for (auto& g : uploaded) im.release_mesh(g);
    throw;
  }
  for (auto& g : uploaded) im.release_mesh(g);
  if (params.silhouette) {
    out.silhouette.resize(out.depth.size());
    for (std::size_t i = 0; i < out.depth.size(); ++i) out.silhouette[i] = out.depth[i] < 1.0f ? 1 : 0;
    if (!params.depth) out.depth.clear();
  }
  return out;
}

std::vector<ViewCapture> Renderer::capture(const Mesh& mesh, const std::vector<CameraMatrices>& cameras,
                                           const CaptureOptions& options) {
  if (mesh.faces.empty()) throw InvalidInput("capture: the mesh has no faces");
  if (options.face_ids && options.back_depth)
    throw InvalidInput(
        "capture: face ids and back depth cannot be asked together (back depth draws with no depth test)");
  mesh.validate();
  if (cameras.empty()) return {};
  const int w = cameras[0].width, h = cameras[0].height;
  check_image_size(w, h);
  for (const CameraMatrices& c : cameras)
    if (c.width != w || c.height != h) throw InvalidInput("capture: every camera must have the same size");
  Impl& im = *impl_;
  Impl::Current cur(im.context);
  const Vec3 origin = bounding_box(mesh).center();
  Impl::GpuMesh g = im.upload(mesh, origin, false, nullptr);
  std::vector<ViewCapture> out;
  out.reserve(cameras.size());
  const bool ids = options.face_ids, range = options.back_depth;
  try {
    im.bind_target(w, h);
    // Only what is asked for is written, so only it is cleared: the colour
    // renderbuffer is not touched (render() clears it).  Depth alone: an
    // empty fragment shader and the depth test; both depths: every fragment
    // blended by MIN into the RG32F buffer, the depth test off.
    if (range) {
      im.ensure_range_buffer();
      im.gl.glDisable(GL_DEPTH_TEST);
      im.gl.glEnable(GL_BLEND);
      im.gl.glBlendEquation(GL_MIN);
    }
    const GLenum buffers[3] = {GL_NONE, GLenum(ids ? GL_COLOR_ATTACHMENT1 : GL_NONE),
                               GLenum(range ? GL_COLOR_ATTACHMENT2 : GL_NONE)};
    im.gl.glDrawBuffers(3, buffers);
    const GLuint program = range ? im.range_program : ids ? im.capture_program : im.depth_program;
    im.gl.glUseProgram(program);
    const GLint mvp_at = im.loc(program, "u_mvp");
    im.gl.glBindVertexArray(g.vao);
    for (const CameraMatrices& cam : cameras) {
      if (range) {
        const GLfloat nothing[4] = {1.f, 1.f, 0.f, 0.f};
        im.gl.glClearBufferfv(GL_COLOR, 2, nothing);
      } else {
        im.clear_depth(ids);
      }
      const Mat4 mvp = cam.projection * cam.view * translation(origin);
      im.gl.glUniformMatrix4fv(mvp_at, 1, GL_FALSE, to_float(mvp).data());
      im.gl.glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
      ViewCapture v;
      v.camera = cam;
      if (range) {
        const std::vector<float> rg = im.read_range(w, h);
        v.depth.resize(std::size_t(w) * h);
        v.back_depth.resize(v.depth.size());
        for (std::size_t i = 0; i < v.depth.size(); ++i) {
          v.depth[i] = rg[2 * i];
          v.back_depth[i] = rg[2 * i] < 1.f ? -rg[2 * i + 1] : 1.f;
        }
      } else {
        v.depth = im.read_depth(w, h);
      }
      if (ids) v.face_ids = im.read_ids(w, h);
      v.silhouette.resize(v.depth.size());
      for (std::size_t i = 0; i < v.depth.size(); ++i) v.silhouette[i] = v.depth[i] < 1.0f ? 1 : 0;
      out.push_back(std::move(v));
      if (options.after_view) options.after_view();
    }
    im.gl.glBindVertexArray(0);
    if (range) im.end_range();
    im.check_errors("capture");
  } catch (...) {
    if (range) im.end_range();
    im.release_mesh(g);
    throw;
  }
  im.release_mesh(g);
  return out;
}

}  // namespace cgview::render
