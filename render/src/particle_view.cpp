/// The 3-D particle view (particle_view.hpp).
///
/// Sections:
///   1. Camera maths     view and projection matrices, fitCamera, projectToPixel, boxEdges,
///                       boundsWith
///   2. Shaders          sphere impostors, screen-space lines, translucent surfaces, the
///                       supersampling box filter
///   3. GL objects       programs, buffers, framebuffers (the Impl)
///   4. Upload and draw  instance data, near/far planes, the draw calls (spheres, lines, the
///                       surfaces sorted back to front, outlines)
///   5. render()         offscreen framebuffer, downsampling, readback
#include "granular/render/particle_view.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

#include "gl_functions.hpp"

namespace granular::render {

// ---------------------------------------------------------------------------------------------
// 1. Camera maths
// ---------------------------------------------------------------------------------------------

namespace {

using Mat4 = Eigen::Matrix4d;

double degToRad(double deg) {
  return deg * std::numbers::pi / 180.0;
}

/// The camera's orthonormal basis: right, up, forward (from the eye towards the target).
struct CameraBasis {
  Vec3 right, up, forward;
};

CameraBasis cameraBasis(const Camera& camera) {
  const Vec3 toTarget = camera.target - camera.eye;
  if (!(toTarget.norm() > 0.0)) throw std::invalid_argument("Camera: eye and target coincide");
  CameraBasis b;
  b.forward = toTarget.normalized();
  Vec3 up = camera.up;
  // An up vector (nearly) parallel to the view direction leaves the roll undefined: fall back
  // to a world axis so that looking straight down still gives an image.
  if (!(up.norm() > 0.0) || std::abs(b.forward.dot(up.normalized())) > 0.999999) {
    up = std::abs(b.forward.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  }
  b.right = b.forward.cross(up).normalized();
  b.up = b.right.cross(b.forward);
  return b;
}

/// World → view (OpenGL convention: the eye at the origin looking down −z), with the world
/// shifted by −origin first. The renderer passes the scene's centre as origin so that the
/// single-precision instance data stays small numbers.
Mat4 viewMatrix(const Camera& camera, const Vec3& origin) {
  const CameraBasis b = cameraBasis(camera);
  Mat4 v = Mat4::Identity();
  v.block<1, 3>(0, 0) = b.right.transpose();
  v.block<1, 3>(1, 0) = b.up.transpose();
  v.block<1, 3>(2, 0) = -b.forward.transpose();
  const Vec3 eye = camera.eye - origin;
  v(0, 3) = -b.right.dot(eye);
  v(1, 3) = -b.up.dot(eye);
  v(2, 3) = b.forward.dot(eye);
  return v;
}

/// gluPerspective: view → clip. near, far > 0 [m].
Mat4 projectionMatrix(double fovYDegrees, double aspect, double near, double far) {
  const double f = 1.0 / std::tan(0.5 * degToRad(fovYDegrees));
  Mat4 p = Mat4::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = (far + near) / (near - far);
  p(2, 3) = 2.0 * far * near / (near - far);
  p(3, 2) = -1.0;
  return p;
}

void checkFov(double fovYDegrees) {
  if (!(fovYDegrees > 0.0 && fovYDegrees < 180.0)) {
    throw std::invalid_argument("Camera: vertical field of view must be in (0, 180) degrees");
  }
}

}  // namespace

std::vector<Segment> boxEdges(const Vec3& boxMin, const Vec3& boxMax, bool openTop) {
  auto corner = [&](int i) {
    return Vec3((i & 1) ? boxMax.x() : boxMin.x(), (i & 2) ? boxMax.y() : boxMin.y(),
                (i & 4) ? boxMax.z() : boxMin.z());
  };
  std::vector<Segment> edges;
  // Corners i and i + bit differ along one axis: each such pair is an edge.
  for (int i = 0; i < 8; ++i) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      if (i & bit) continue;
      const bool top = (i & 4) && (bit != 4);
      if (openTop && top) continue;
      edges.emplace_back(corner(i), corner(i | bit));
    }
  }
  return edges;
}

std::pair<Vec3, Vec3> boundsWith(const Vec3& boxMin, const Vec3& boxMax,
                                 std::span<const Triangle> surfaces,
                                 std::span<const Segment> outlines) {
  Vec3 lo = boxMin, hi = boxMax;
  for (const Triangle& t : surfaces) {
    for (const Vec3& corner : t) {
      lo = lo.cwiseMin(corner);
      hi = hi.cwiseMax(corner);
    }
  }
  for (const auto& [a, b] : outlines) {
    lo = lo.cwiseMin(a).cwiseMin(b);
    hi = hi.cwiseMax(a).cwiseMax(b);
  }
  return {lo, hi};
}

Camera fitCamera(const Vec3& boxMin, const Vec3& boxMax, double azimuthDeg, double elevationDeg,
                 double fovY, double aspect, double margin) {
  checkFov(fovY);
  if (!(aspect > 0.0)) throw std::invalid_argument("fitCamera: aspect must be positive");
  if (!(margin >= 0.0 && margin < 1.0)) {
    throw std::invalid_argument("fitCamera: margin must be in [0, 1)");
  }
  const double az = degToRad(azimuthDeg), el = degToRad(elevationDeg);
  const Vec3 toEye(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const Vec3 horizontal(std::cos(az), std::sin(az), 0.0);

  Camera camera;
  camera.fovYDegrees = fovY;
  camera.target = 0.5 * (boxMin + boxMax);
  // Straight up or down, z is the view direction; take the limit of a slightly smaller
  // elevation instead (the image's up is then horizontal).
  camera.up = std::abs(std::cos(el)) < 1e-9 ? Vec3(-std::copysign(1.0, std::sin(el)) * horizontal)
                                            : Vec3::UnitZ();
  camera.eye = camera.target + toEye;  // unit distance, only to get the basis
  const CameraBasis b = cameraBasis(camera);

  // Corner q (relative to the target) lies at depth d + q·f from an eye at distance d, and is
  // inside the image when |q·r| <= tanX (d + q·f) and |q·u| <= tanY (d + q·f): each corner
  // and each axis gives a lower bound on d.
  const double tanY = std::tan(0.5 * degToRad(fovY)) * (1.0 - margin);
  const double tanX = tanY * aspect;
  const double diagonal = (boxMax - boxMin).norm();
  double distance = 0.0;
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? boxMax.x() : boxMin.x(), (i & 2) ? boxMax.y() : boxMin.y(),
                      (i & 4) ? boxMax.z() : boxMin.z());
    const Vec3 q = corner - camera.target;
    const double depthOffset = q.dot(b.forward);
    distance = std::max({distance, std::abs(q.dot(b.right)) / tanX - depthOffset,
                         std::abs(q.dot(b.up)) / tanY - depthOffset,
                         -depthOffset + 1e-3 * diagonal});  // every corner in front of the eye
  }
  if (!(distance > 0.0)) distance = 1.0;  // a point-sized box: any distance frames it
  camera.eye = camera.target + distance * toEye;
  return camera;
}

std::optional<Eigen::Vector2d> projectToPixel(const Camera& camera, int width, int height,
                                              const Vec3& point) {
  checkFov(camera.fovYDegrees);
  const CameraBasis b = cameraBasis(camera);
  const Vec3 q = point - camera.eye;
  const double depth = q.dot(b.forward);
  if (!(depth > 0.0)) return std::nullopt;
  const double tanY = std::tan(0.5 * degToRad(camera.fovYDegrees));
  const double aspect = double(width) / height;
  const double ndcX = q.dot(b.right) / (depth * tanY * aspect);
  const double ndcY = q.dot(b.up) / (depth * tanY);
  return Eigen::Vector2d(0.5 * (ndcX + 1.0) * width, 0.5 * (1.0 - ndcY) * height);
}

// ---------------------------------------------------------------------------------------------
// 2. Shaders
// ---------------------------------------------------------------------------------------------

namespace {

/// Sphere impostor, vertex stage. One instance per sphere, four vertices (a triangle strip)
/// per instance, corner chosen by gl_VertexID. The quad lies in the plane through the centre
/// perpendicular to the eye→centre ray, with half-size R·d/√(d² − R²): the cross-section of
/// the cone of rays tangent to the sphere, so it covers the silhouette exactly (a camera-facing
/// quad of half-size R would clip the silhouette of a near, off-axis sphere).
constexpr const char* kSphereVertex = R"(#version 330 core
layout(location = 0) in vec4 aSphere;  // centre (world minus origin) [m], radius [m]
layout(location = 1) in vec4 aColour;  // RGBA8, normalised
uniform mat4 uView;
uniform mat4 uProjection;
out vec3 vPoint;        // view-space point on the quad
flat out vec3 vCentre;  // view-space centre
flat out vec2 vRadius;  // R, 1/R
flat out vec3 vColour;
void main() {
  vec3 c = (uView * vec4(aSphere.xyz, 1.0)).xyz;
  float r = aSphere.w;
  float d2 = dot(c, c);
  vCentre = c;
  vRadius = vec2(r, 1.0 / r);
  vColour = aColour.rgb;
  vPoint = c;
  if (d2 <= r * r * 1.0001) {  // the eye is inside the sphere: draw nothing
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec3 w = c * inversesqrt(d2);
  vec3 helper = abs(w.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 u = normalize(cross(helper, w));
  vec3 v = cross(w, u);
  float halfSize = r * sqrt(d2 / (d2 - r * r));
  vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
  vPoint = c + halfSize * (corner.x * u + corner.y * v);
  gl_Position = uProjection * vec4(vPoint, 1.0);
}
)";

/// Sphere impostor, fragment stage: ray–sphere intersection, true depth, head-light shading.
/// The fragment shader is where llvmpipe spends the time (every covered sample runs it: a
/// shader that writes gl_FragDepth gets no early depth test), so it is kept lean: depth from
/// two projection terms instead of a matrix product, no pow(), no per-fragment half vector.
/// The discriminant is computed as R² − |c − (c·ŝ)ŝ|² (distance of the centre from the ray)
/// rather than (c·ŝ)² − |c|² + R², which loses all digits in single precision when the sphere
/// is small and far away.
constexpr const char* kSphereFragment = R"(#version 330 core
in vec3 vPoint;
flat in vec3 vCentre;
flat in vec2 vRadius;  // R, 1/R
flat in vec3 vColour;
uniform vec2 uDepth;  // window depth = uDepth.x + uDepth.y / z (view-space z of the hit)
out vec4 fragColour;
// Light fixed to the camera, a little above and left of the eye (a light exactly at the eye
// puts every highlight dead centre and makes the spheres look flat).
const vec3 kLight = normalize(vec3(-0.3, 0.4, 1.0));
// Blinn half vector for a viewer at infinity: the true per-fragment view direction moves the
// soft highlight imperceptibly and would cost a normalisation per fragment.
const vec3 kHalf = normalize(kLight + vec3(0.0, 0.0, 1.0));
const float kAmbient = 0.25;
const float kDiffuse = 0.75;
const float kSpecular = 0.25;
void main() {
  vec3 s = normalize(vPoint);
  float along = dot(vCentre, s);
  vec3 offset = vCentre - along * s;
  float disc = vRadius.x * vRadius.x - dot(offset, offset);
  if (disc < 0.0) discard;
  vec3 p = (along - sqrt(disc)) * s;
  vec3 n = (p - vCentre) * vRadius.y;
  gl_FragDepth = uDepth.x + uDepth.y / p.z;
  float lambert = max(dot(n, kLight), 0.0);
  // Shininess 32 by squaring: pow() is exp2(log2()) in llvmpipe, dearer than the rest of the
  // shader together.
  float highlight = max(dot(n, kHalf), 0.0);
  highlight *= highlight;
  highlight *= highlight;
  highlight *= highlight;
  highlight *= highlight;
  highlight *= highlight;
  vec3 rgb = vColour * (kAmbient + kDiffuse * lambert) + vec3(kSpecular * highlight);
  fragColour = vec4(min(rgb, vec3(1.0)), 1.0);
}
)";

/// Line segments as screen-space quads of constant pixel width, extended by half the width at
/// both ends so that edges meeting at a box corner close the corner. A segment crossing the
/// near plane is cut there first (the division by w would fold the far end back).
constexpr const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 aFrom;  // world minus origin [m]
layout(location = 1) in vec3 aTo;
uniform mat4 uView;
uniform mat4 uProjection;
uniform vec2 uViewport;    // [px]
uniform float uHalfWidth;  // [px]
uniform float uNear;       // near-plane distance [m]
void main() {
  vec3 a = (uView * vec4(aFrom, 1.0)).xyz;
  vec3 b = (uView * vec4(aTo, 1.0)).xyz;
  float limit = -uNear * 1.0001;
  if (a.z > limit && b.z > limit) {  // wholly behind the near plane
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  if (a.z > limit) a = mix(a, b, (limit - a.z) / (b.z - a.z));
  if (b.z > limit) b = mix(b, a, (limit - b.z) / (a.z - b.z));
  vec4 ca = uProjection * vec4(a, 1.0);
  vec4 cb = uProjection * vec4(b, 1.0);
  vec2 halfViewport = 0.5 * uViewport;
  vec2 sa = ca.xy / ca.w * halfViewport;
  vec2 sb = cb.xy / cb.w * halfViewport;
  vec2 d = sb - sa;
  float len = length(d);
  vec2 dir = len > 1e-6 ? d / len : vec2(1.0, 0.0);
  vec2 normal = vec2(-dir.y, dir.x);
  bool atEnd = (gl_VertexID & 1) != 0;
  float side = (gl_VertexID & 2) != 0 ? 1.0 : -1.0;
  vec4 clip = atEnd ? cb : ca;
  vec2 offsetPx = uHalfWidth * (side * normal + (atEnd ? 1.0 : -1.0) * dir);
  clip.xy += offsetPx / halfViewport * clip.w;
  gl_Position = clip;
}
)";

constexpr const char* kLineFragment = R"(#version 330 core
uniform vec4 uColour;
out vec4 fragColour;
void main() { fragColour = uColour; }
)";

/// Translucent surfaces: plain triangles, one flat normal per triangle (world minus origin).
/// Each corner is drawn a thousandth of its distance nearer the eye, which moves it along its
/// own ray (the same pixel) and only changes its depth: a sphere pressing slightly into a wall,
/// as a settled bed does, stays behind it instead of poking through as a spot of untinted
/// colour.
constexpr const char* kSurfaceVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;  // [m]
layout(location = 1) in vec3 aNormal;    // unit, the triangle's
uniform mat4 uView;
uniform mat4 uProjection;
out vec3 vPoint;   // view space
out vec3 vNormal;  // view space
void main() {
  vec4 p = uView * vec4(aPosition, 1.0);
  p.xyz *= 0.999;
  vPoint = p.xyz;
  vNormal = mat3(uView) * aNormal;
  gl_Position = uProjection * p;
}
)";

/// Surfaces, fragment stage: both sides lit alike by the spheres' light (a wall has no
/// outside), dimmer where it faces away from it, so that the facets of a curved wall differ in
/// brightness. The opacity grows towards grazing views: a cylinder is fainter face-on in its
/// middle than near its silhouette, as a glass tube looks, and its outline reads as a curve.
constexpr const char* kSurfaceFragment = R"(#version 330 core
in vec3 vPoint;
in vec3 vNormal;
uniform vec4 uColour;  // RGBA, normalised; alpha = face-on opacity
out vec4 fragColour;
const vec3 kLight = normalize(vec3(-0.3, 0.4, 1.0));
void main() {
  vec3 n = normalize(vNormal);
  float facing = abs(dot(n, normalize(-vPoint)));
  float lit = abs(dot(n, kLight));
  vec3 rgb = uColour.rgb * (0.6 + 0.4 * lit);
  float grazing = 1.0 - facing;
  float alpha = uColour.a + (1.0 - uColour.a) * 0.5 * grazing * grazing * grazing;
  fragColour = vec4(rgb, alpha);
}
)";

/// Full-screen triangle (no vertex buffer: positions from gl_VertexID).
constexpr const char* kFullScreenVertex = R"(#version 330 core
void main() {
  vec2 p = vec2((gl_VertexID & 1) != 0 ? 3.0 : -1.0, (gl_VertexID & 2) != 0 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

/// Box filter for supersampling: each output pixel is the mean of its factor × factor block,
/// computed in integers (sum of 8-bit values, rounded division) so that the result is exact
/// and does not depend on the order of float additions.
constexpr const char* kDownsampleFragment = R"(#version 330 core
uniform sampler2D uSource;
uniform int uFactor;
out vec4 fragColour;
void main() {
  ivec2 base = ivec2(gl_FragCoord.xy) * uFactor;
  ivec4 sum = ivec4(0);
  for (int j = 0; j < uFactor; ++j)
    for (int i = 0; i < uFactor; ++i)
      sum += ivec4(texelFetch(uSource, base + ivec2(i, j), 0) * 255.0 + 0.5);
  int n = uFactor * uFactor;
  fragColour = vec4((sum + n / 2) / n) / 255.0;
}
)";

}  // namespace

// ---------------------------------------------------------------------------------------------
// 3. GL objects
// ---------------------------------------------------------------------------------------------

namespace {

/// Per-sphere instance data: 20 bytes, one interleaved VBO.
struct SphereInstance {
  float x, y, z, radius;  // [m], relative to the scene origin
  std::array<std::uint8_t, 4> rgba;
};
static_assert(sizeof(SphereInstance) == 20);

struct LineInstance {
  float from[3], to[3];  // [m], relative to the scene origin
};
static_assert(sizeof(LineInstance) == 24);

/// One corner of a surface triangle, with the triangle's normal.
struct SurfaceVertex {
  float position[3];  // [m], relative to the scene origin
  float normal[3];
};
static_assert(sizeof(SurfaceVertex) == 24);

/// A surface triangle as uploaded: corners relative to the scene origin [m], unit normal
/// (zero for a degenerate triangle, which covers no pixel).
struct SurfaceTriangle {
  Vec3 corner[3];
  Vec3 normal;
};

GLuint compileShader(const GlFunctions& gl, GLenum type, const char* source, const char* what) {
  const GLuint shader = gl.CreateShader(type);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::array<char, 4096> log{};
    gl.GetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    gl.DeleteShader(shader);
    throw RenderError(std::string("ParticleRenderer: ") + what + " shader: " + log.data());
  }
  return shader;
}

GLuint linkProgram(const GlFunctions& gl, const char* vertex, const char* fragment,
                   const char* what) {
  const GLuint vs = compileShader(gl, GL_VERTEX_SHADER, vertex, what);
  GLuint fs = 0;
  try {
    fs = compileShader(gl, GL_FRAGMENT_SHADER, fragment, what);
  } catch (...) {
    gl.DeleteShader(vs);
    throw;
  }
  const GLuint program = gl.CreateProgram();
  gl.AttachShader(program, vs);
  gl.AttachShader(program, fs);
  gl.LinkProgram(program);
  gl.DetachShader(program, vs);
  gl.DetachShader(program, fs);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::array<char, 4096> log{};
    gl.GetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
    gl.DeleteProgram(program);
    throw RenderError(std::string("ParticleRenderer: ") + what + " program: " + log.data());
  }
  return program;
}

Eigen::Matrix4f toFloat(const Mat4& m) {
  return m.cast<float>();
}

}  // namespace

struct ParticleRenderer::Impl {
  GlFunctions gl;

  GLuint sphereProgram = 0, lineProgram = 0, surfaceProgram = 0, downsampleProgram = 0;
  GLint sphereView = -1, sphereProjection = -1, sphereDepth = -1;
  GLint lineView = -1, lineProjection = -1, lineViewport = -1, lineHalfWidth = -1, lineNear = -1,
        lineColour = -1;
  GLint surfaceView = -1, surfaceProjection = -1, surfaceColour = -1;
  GLint downsampleSource = -1, downsampleFactor = -1;

  GLuint sphereVao = 0, sphereVbo = 0, lineVao = 0, lineVbo = 0, outlineVao = 0, outlineVbo = 0,
         surfaceVao = 0, surfaceVbo = 0, emptyVao = 0;

  // Offscreen targets: the supersampled colour texture + depth, and the output-size colour.
  GLuint sceneFbo = 0, sceneColour = 0, sceneDepth = 0;
  int sceneWidth = 0, sceneHeight = 0;
  GLuint outputFbo = 0, outputColour = 0;
  int outputWidth = 0, outputHeight = 0;

  // The uploaded scene.
  GLsizei sphereCount = 0, lineCount = 0, outlineCount = 0;
  Vec3 origin = Vec3::Zero();  // subtracted from every position before conversion to float
  Vec3 boundsMin = Vec3::Zero(), boundsMax = Vec3::Zero();
  Rgba lineRgba{}, outlineRgba{}, surfaceRgba{};
  double lineWidth = 0.0;
  std::vector<SphereInstance> sphereStaging;
  std::vector<LineInstance> lineStaging;
  std::vector<SurfaceTriangle> surfaceTriangles;  // sorted anew for each camera
  std::vector<std::pair<double, std::size_t>> surfaceOrder;
  std::vector<SurfaceVertex> surfaceStaging;

  explicit Impl(GlProcLoader loader) : gl(loader) {
    try {
      create();
    } catch (...) {
      release();  // the destructor does not run for a half-built object
      throw;
    }
  }

  ~Impl() { release(); }

  void create() {
    sphereProgram = linkProgram(gl, kSphereVertex, kSphereFragment, "sphere");
    lineProgram = linkProgram(gl, kLineVertex, kLineFragment, "line");
    surfaceProgram = linkProgram(gl, kSurfaceVertex, kSurfaceFragment, "surface");
    downsampleProgram = linkProgram(gl, kFullScreenVertex, kDownsampleFragment, "downsample");
    sphereView = gl.GetUniformLocation(sphereProgram, "uView");
    sphereProjection = gl.GetUniformLocation(sphereProgram, "uProjection");
    sphereDepth = gl.GetUniformLocation(sphereProgram, "uDepth");
    lineView = gl.GetUniformLocation(lineProgram, "uView");
    lineProjection = gl.GetUniformLocation(lineProgram, "uProjection");
    lineViewport = gl.GetUniformLocation(lineProgram, "uViewport");
    lineHalfWidth = gl.GetUniformLocation(lineProgram, "uHalfWidth");
    lineNear = gl.GetUniformLocation(lineProgram, "uNear");
    lineColour = gl.GetUniformLocation(lineProgram, "uColour");
    surfaceView = gl.GetUniformLocation(surfaceProgram, "uView");
    surfaceProjection = gl.GetUniformLocation(surfaceProgram, "uProjection");
    surfaceColour = gl.GetUniformLocation(surfaceProgram, "uColour");
    downsampleSource = gl.GetUniformLocation(downsampleProgram, "uSource");
    downsampleFactor = gl.GetUniformLocation(downsampleProgram, "uFactor");

    // Spheres: attribute 0 = centre + radius, 1 = colour, both advancing once per instance.
    gl.GenVertexArrays(1, &sphereVao);
    gl.GenBuffers(1, &sphereVbo);
    gl.BindVertexArray(sphereVao);
    gl.BindBuffer(GL_ARRAY_BUFFER, sphereVbo);
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(SphereInstance), nullptr);
    gl.VertexAttribDivisor(0, 1);
    gl.EnableVertexAttribArray(1);
    gl.VertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(SphereInstance),
                           reinterpret_cast<const void*>(offsetof(SphereInstance, rgba)));
    gl.VertexAttribDivisor(1, 1);

    // Lines and outlines: the same layout, one instance per segment.
    for (auto [vao, vbo] : {std::pair{&lineVao, &lineVbo}, std::pair{&outlineVao, &outlineVbo}}) {
      gl.GenVertexArrays(1, vao);
      gl.GenBuffers(1, vbo);
      gl.BindVertexArray(*vao);
      gl.BindBuffer(GL_ARRAY_BUFFER, *vbo);
      gl.EnableVertexAttribArray(0);
      gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineInstance), nullptr);
      gl.VertexAttribDivisor(0, 1);
      gl.EnableVertexAttribArray(1);
      gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(LineInstance),
                             reinterpret_cast<const void*>(offsetof(LineInstance, to)));
      gl.VertexAttribDivisor(1, 1);
    }

    // Surfaces: plain vertices, position and normal.
    gl.GenVertexArrays(1, &surfaceVao);
    gl.GenBuffers(1, &surfaceVbo);
    gl.BindVertexArray(surfaceVao);
    gl.BindBuffer(GL_ARRAY_BUFFER, surfaceVbo);
    gl.EnableVertexAttribArray(0);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(SurfaceVertex), nullptr);
    gl.EnableVertexAttribArray(1);
    gl.VertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(SurfaceVertex),
                           reinterpret_cast<const void*>(offsetof(SurfaceVertex, normal)));

    // The core profile draws nothing without a bound vertex array, even attribute-less.
    gl.GenVertexArrays(1, &emptyVao);
    gl.BindVertexArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    checkError("setting up");
  }

  /// Deletes every GL object (names still 0 are ignored by GL).
  void release() {
    releaseTargets();
    const GLuint vaos[] = {sphereVao, lineVao, outlineVao, surfaceVao, emptyVao};
    gl.DeleteVertexArrays(5, vaos);
    const GLuint buffers[] = {sphereVbo, lineVbo, outlineVbo, surfaceVbo};
    gl.DeleteBuffers(4, buffers);
    gl.DeleteProgram(sphereProgram);
    gl.DeleteProgram(lineProgram);
    gl.DeleteProgram(surfaceProgram);
    gl.DeleteProgram(downsampleProgram);
    sphereVao = lineVao = outlineVao = surfaceVao = emptyVao = 0;
    sphereVbo = lineVbo = outlineVbo = surfaceVbo = 0;
    sphereProgram = lineProgram = surfaceProgram = downsampleProgram = 0;
  }

  void checkError(const char* when) const {
    const GLenum error = gl.GetError();
    if (error != GL_NO_ERROR) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%04X", unsigned(error));
      throw RenderError(std::string("ParticleRenderer: GL error ") + hex + " while " + when);
    }
  }

  void releaseTargets() {
    const GLuint fbos[] = {sceneFbo, outputFbo};
    gl.DeleteFramebuffers(2, fbos);
    const GLuint textures[] = {sceneColour, outputColour};
    gl.DeleteTextures(2, textures);
    gl.DeleteRenderbuffers(1, &sceneDepth);
    sceneFbo = sceneColour = sceneDepth = outputFbo = outputColour = 0;
    sceneWidth = sceneHeight = outputWidth = outputHeight = 0;
  }

  GLuint makeColourTexture(int width, int height) {
    GLuint texture = 0;
    gl.GenTextures(1, &texture);
    gl.BindTexture(GL_TEXTURE_2D, texture);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    // Read with texelFetch only; nearest and no mipmaps keep the texture complete.
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    gl.BindTexture(GL_TEXTURE_2D, 0);
    return texture;
  }

  void checkComplete(const char* what) {
    const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      throw RenderError(std::string("ParticleRenderer: incomplete ") + what + " framebuffer");
    }
  }

  /// (Re)creates the offscreen targets when the size changes. Leaves GL_FRAMEBUFFER bound to
  /// something of ours: the caller restores its binding.
  void ensureTargets(int width, int height, int supersample) {
    const int w = width * supersample, h = height * supersample;
    GLint maxTexture = 0, maxRenderbuffer = 0, maxViewport[2] = {0, 0};
    gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRenderbuffer);
    gl.GetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    const int limit = std::min({maxTexture, maxRenderbuffer, maxViewport[0], maxViewport[1]});
    if (w > limit || h > limit) {
      throw RenderError("ParticleRenderer: " + std::to_string(w) + " x " + std::to_string(h) +
                        " px (size x supersampling) exceeds the GL limit of " +
                        std::to_string(limit) + " px; lower the supersampling factor");
    }
    if (w != sceneWidth || h != sceneHeight) {
      if (sceneFbo) {
        gl.DeleteFramebuffers(1, &sceneFbo);
        gl.DeleteTextures(1, &sceneColour);
        gl.DeleteRenderbuffers(1, &sceneDepth);
      }
      sceneColour = makeColourTexture(w, h);
      gl.GenRenderbuffers(1, &sceneDepth);
      gl.BindRenderbuffer(GL_RENDERBUFFER, sceneDepth);
      gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
      gl.BindRenderbuffer(GL_RENDERBUFFER, 0);
      gl.GenFramebuffers(1, &sceneFbo);
      gl.BindFramebuffer(GL_FRAMEBUFFER, sceneFbo);
      gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, sceneColour, 0);
      gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, sceneDepth);
      checkComplete("scene");
      sceneWidth = w;
      sceneHeight = h;
    }
    if (supersample > 1 && (width != outputWidth || height != outputHeight)) {
      if (outputFbo) {
        gl.DeleteFramebuffers(1, &outputFbo);
        gl.DeleteTextures(1, &outputColour);
      }
      outputColour = makeColourTexture(width, height);
      gl.GenFramebuffers(1, &outputFbo);
      gl.BindFramebuffer(GL_FRAMEBUFFER, outputFbo);
      gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, outputColour, 0);
      checkComplete("output");
      outputWidth = width;
      outputHeight = height;
    }
  }

  // -------------------------------------------------------------------------------------------
  // 4. Upload and draw
  // -------------------------------------------------------------------------------------------

  void upload(const ParticleScene& scene) {
    const std::size_t n = scene.centres.size();
    if (scene.radii.size() != n) {
      throw std::invalid_argument("ParticleScene: " + std::to_string(scene.radii.size()) +
                                  " radii for " + std::to_string(n) + " centres");
    }
    if (!scene.colours.empty() && scene.colours.size() != n) {
      throw std::invalid_argument("ParticleScene: " + std::to_string(scene.colours.size()) +
                                  " colours for " + std::to_string(n) + " centres");
    }
    constexpr std::size_t kMaxDraw = std::size_t(std::numeric_limits<GLsizei>::max());
    if (n > kMaxDraw || scene.lines.size() > kMaxDraw || scene.outlines.size() > kMaxDraw ||
        scene.surfaces.size() > kMaxDraw / 3) {
      throw std::invalid_argument(
          "ParticleScene: too many spheres, lines or surfaces for one draw call");
    }

    // Bounds of everything drawn: the origin for single precision, and the near/far planes.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    for (std::size_t i = 0; i < n; ++i) {
      const double r = std::abs(scene.radii[i]);
      lo = lo.cwiseMin(scene.centres[i] - Vec3::Constant(r));
      hi = hi.cwiseMax(scene.centres[i] + Vec3::Constant(r));
    }
    for (const auto& [a, b] : scene.lines) {
      lo = lo.cwiseMin(a).cwiseMin(b);
      hi = hi.cwiseMax(a).cwiseMax(b);
    }
    // Surfaces widen the bounds only when there are some: a scene without them keeps the
    // origin and depth range, and so its image, bit for bit.
    if (!scene.surfaces.empty() || !scene.outlines.empty()) {
      std::tie(lo, hi) = boundsWith(lo, hi, scene.surfaces, scene.outlines);
    }
    if (!(lo.array() <= hi.array()).all()) lo = hi = Vec3::Zero();  // empty scene
    if (!lo.allFinite() || !hi.allFinite()) {
      throw std::invalid_argument(
          "ParticleScene: non-finite centre, radius, line end or surface corner");
    }
    boundsMin = lo;
    boundsMax = hi;
    origin = 0.5 * (lo + hi);

    sphereStaging.resize(n);
    const Rgba fallback = scene.defaultColour;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 c = scene.centres[i] - origin;
      const Rgba colour = scene.colours.empty() ? fallback : scene.colours[i];
      sphereStaging[i] = {float(c.x()),
                          float(c.y()),
                          float(c.z()),
                          float(std::abs(scene.radii[i])),
                          {colour.r, colour.g, colour.b, 255}};
    }
    uploadSegments(scene.lines, lineVbo);
    uploadSegments(scene.outlines, outlineVbo);
    surfaceTriangles.resize(scene.surfaces.size());
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      SurfaceTriangle& t = surfaceTriangles[i];
      for (int k = 0; k < 3; ++k) t.corner[k] = scene.surfaces[i][std::size_t(k)] - origin;
      const Vec3 n = (t.corner[1] - t.corner[0]).cross(t.corner[2] - t.corner[0]);
      t.normal = n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3::Zero();
    }

    gl.BindBuffer(GL_ARRAY_BUFFER, sphereVbo);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(n * sizeof(SphereInstance)),
                  n ? sphereStaging.data() : nullptr, GL_STREAM_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    sphereCount = GLsizei(n);
    lineCount = GLsizei(scene.lines.size());
    outlineCount = GLsizei(scene.outlines.size());
    lineRgba = scene.lineColour;
    outlineRgba = scene.outlineColour;
    surfaceRgba = scene.surfaceColour;
    lineWidth = scene.lineWidth;
    checkError("uploading the scene");
  }

  /// Segments relative to the origin, into `vbo` (left bound).
  void uploadSegments(std::span<const Segment> segments, GLuint vbo) {
    lineStaging.resize(segments.size());
    for (std::size_t i = 0; i < segments.size(); ++i) {
      const Vec3 a = segments[i].first - origin, b = segments[i].second - origin;
      lineStaging[i] = {{float(a.x()), float(a.y()), float(a.z())},
                        {float(b.x()), float(b.y()), float(b.z())}};
    }
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(lineStaging.size() * sizeof(LineInstance)),
                  lineStaging.empty() ? nullptr : lineStaging.data(), GL_STREAM_DRAW);
  }

  /// The surface triangles back to front as `view` sees them (by the depth of their centroids,
  /// ties by index, so that the order and the image do not depend on the sort), into the
  /// surface buffer.
  void uploadSortedSurfaces(const Mat4& view) {
    const Eigen::RowVector3d depthRow = view.block<1, 3>(2, 0);
    surfaceOrder.resize(surfaceTriangles.size());
    for (std::size_t i = 0; i < surfaceTriangles.size(); ++i) {
      const SurfaceTriangle& t = surfaceTriangles[i];
      // View-space z is negative in front of the eye: the most negative is the farthest.
      surfaceOrder[i] = {depthRow.dot(t.corner[0] + t.corner[1] + t.corner[2]), i};
    }
    std::sort(surfaceOrder.begin(), surfaceOrder.end());
    surfaceStaging.resize(3 * surfaceTriangles.size());
    for (std::size_t i = 0; i < surfaceOrder.size(); ++i) {
      const SurfaceTriangle& t = surfaceTriangles[surfaceOrder[i].second];
      for (int k = 0; k < 3; ++k) {
        surfaceStaging[3 * i + std::size_t(k)] = {
            {float(t.corner[k].x()), float(t.corner[k].y()), float(t.corner[k].z())},
            {float(t.normal.x()), float(t.normal.y()), float(t.normal.z())}};
      }
    }
    gl.BindBuffer(GL_ARRAY_BUFFER, surfaceVbo);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(surfaceStaging.size() * sizeof(SurfaceVertex)),
                  surfaceStaging.data(), GL_STREAM_DRAW);
    gl.BindBuffer(GL_ARRAY_BUFFER, 0);
  }

  void draw(const Camera& camera, int width, int height, double pixelScale) {
    checkFov(camera.fovYDegrees);
    if (width <= 0 || height <= 0) throw std::invalid_argument("draw: non-positive size");
    const Mat4 view = viewMatrix(camera, origin);

    // Near and far planes from the bounds' corners: as tight as the scene allows, which keeps
    // the 24-bit depth buffer's resolution where the spheres are. If the eye is inside the
    // bounds, the near plane stops at 1e-4 of the far one.
    double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner((i & 1) ? boundsMax.x() : boundsMin.x(),
                        (i & 2) ? boundsMax.y() : boundsMin.y(),
                        (i & 4) ? boundsMax.z() : boundsMin.z());
      const double depth = -(view.block<1, 3>(2, 0).dot(corner - origin) + view(2, 3));
      nearest = std::min(nearest, depth);
      farthest = std::max(farthest, depth);
    }
    if (!(farthest > 0.0)) return;  // everything behind the eye
    const double far = farthest * 1.01 + 1e-9;
    const double near = std::max(nearest * 0.99, far * 1e-4);
    const Mat4 projection = projectionMatrix(camera.fovYDegrees, double(width) / height, near, far);
    const Eigen::Matrix4f viewF = toFloat(view), projectionF = toFloat(projection);

    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LEQUAL);
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_BLEND);
    gl.Disable(GL_CULL_FACE);

    if (sphereCount > 0) {
      gl.UseProgram(sphereProgram);
      gl.UniformMatrix4fv(sphereView, 1, GL_FALSE, viewF.data());
      gl.UniformMatrix4fv(sphereProjection, 1, GL_FALSE, projectionF.data());
      // Window depth 0.5·(clip.z / clip.w) + 0.5 with clip.z = P22·z + P23, clip.w = −z.
      gl.Uniform2f(sphereDepth, float(0.5 - 0.5 * projection(2, 2)),
                   float(-0.5 * projection(2, 3)));
      gl.BindVertexArray(sphereVao);
      gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, sphereCount);
    }
    auto drawSegments = [&](GLuint vao, GLsizei count, Rgba rgba) {
      if (count == 0 || !(lineWidth > 0.0)) return;
      gl.UseProgram(lineProgram);
      gl.UniformMatrix4fv(lineView, 1, GL_FALSE, viewF.data());
      gl.UniformMatrix4fv(lineProjection, 1, GL_FALSE, projectionF.data());
      gl.Uniform2f(lineViewport, float(width), float(height));
      gl.Uniform1f(lineHalfWidth, float(0.5 * lineWidth * pixelScale));
      gl.Uniform1f(lineNear, float(near));
      gl.Uniform4f(lineColour, rgba.r / 255.0f, rgba.g / 255.0f, rgba.b / 255.0f, 1.0f);
      gl.BindVertexArray(vao);
      gl.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, count);
    };
    drawSegments(lineVao, lineCount, lineRgba);
    if (!surfaceTriangles.empty()) {
      uploadSortedSurfaces(view);
      gl.UseProgram(surfaceProgram);
      gl.UniformMatrix4fv(surfaceView, 1, GL_FALSE, viewF.data());
      gl.UniformMatrix4fv(surfaceProjection, 1, GL_FALSE, projectionF.data());
      gl.Uniform4f(surfaceColour, surfaceRgba.r / 255.0f, surfaceRgba.g / 255.0f,
                   surfaceRgba.b / 255.0f, surfaceRgba.a / 255.0f);
      // Blend the colour; keep the target's alpha (the image stays opaque). Depth writes off:
      // a surface never hides what lies behind it.
      gl.Enable(GL_BLEND);
      gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
      gl.DepthMask(GL_FALSE);
      gl.BindVertexArray(surfaceVao);
      gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(3 * surfaceTriangles.size()));
      gl.DepthMask(GL_TRUE);
      gl.Disable(GL_BLEND);
    }
    // The outlines last, untinted: they lie on their own surfaces, whose tint would cover them
    // in patches where the two depths tie.
    drawSegments(outlineVao, outlineCount, outlineRgba);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    checkError("drawing");
  }

  // -------------------------------------------------------------------------------------------
  // 5. render()
  // -------------------------------------------------------------------------------------------

  Image render(const ParticleScene& scene, const Camera& camera, int width, int height,
               int supersample) {
    if (width <= 0 || height <= 0) {
      throw std::invalid_argument("ParticleRenderer::render: non-positive image size");
    }
    if (supersample < 1) {
      throw std::invalid_argument("ParticleRenderer::render: supersample must be >= 1");
    }
    checkFov(camera.fovYDegrees);
    upload(scene);

    GLint previousDraw = 0, previousRead = 0, previousViewport[4] = {0, 0, 0, 0};
    gl.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previousDraw);
    gl.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &previousRead);
    gl.GetIntegerv(GL_VIEWPORT, previousViewport);
    struct Restore {
      const GlFunctions& gl;
      GLint draw, read;
      const GLint* viewport;
      ~Restore() {
        gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(draw));
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(read));
        gl.Viewport(viewport[0], viewport[1], viewport[2], viewport[3]);
      }
    } restore{gl, previousDraw, previousRead, previousViewport};

    ensureTargets(width, height, supersample);

    // Draw at the supersampled size.
    gl.BindFramebuffer(GL_FRAMEBUFFER, sceneFbo);
    gl.Viewport(0, 0, sceneWidth, sceneHeight);
    gl.Disable(GL_SCISSOR_TEST);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const Rgba bg = scene.background;
    gl.ClearColor(bg.r / 255.0f, bg.g / 255.0f, bg.b / 255.0f, 1.0f);
    gl.DepthMask(GL_TRUE);
    gl.ClearDepth(1.0);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    draw(camera, sceneWidth, sceneHeight, supersample);

    // Box-filter down to the output size.
    GLuint readFbo = sceneFbo;
    if (supersample > 1) {
      gl.BindFramebuffer(GL_FRAMEBUFFER, outputFbo);
      gl.Viewport(0, 0, width, height);
      gl.Disable(GL_DEPTH_TEST);
      gl.UseProgram(downsampleProgram);
      gl.ActiveTexture(GL_TEXTURE0);
      gl.BindTexture(GL_TEXTURE_2D, sceneColour);
      gl.Uniform1i(downsampleSource, 0);
      gl.Uniform1i(downsampleFactor, supersample);
      gl.BindVertexArray(emptyVao);
      gl.DrawArrays(GL_TRIANGLES, 0, 3);
      gl.BindVertexArray(0);
      gl.BindTexture(GL_TEXTURE_2D, 0);
      gl.UseProgram(0);
      readFbo = outputFbo;
    }

    // Read back; GL's rows run bottom-up, Image's top-down.
    Image image(width, height);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    checkError("reading back");
    const std::size_t row = std::size_t(width) * 4;
    std::vector<std::uint8_t> swap(row);
    for (int y = 0; y < height / 2; ++y) {
      std::uint8_t* top = image.pixels.data() + std::size_t(y) * row;
      std::uint8_t* bottom = image.pixels.data() + std::size_t(height - 1 - y) * row;
      std::memcpy(swap.data(), top, row);
      std::memcpy(top, bottom, row);
      std::memcpy(bottom, swap.data(), row);
    }
    return image;
  }
};

ParticleRenderer::ParticleRenderer(GlProcLoader loader) : impl_(std::make_unique<Impl>(loader)) {}
ParticleRenderer::~ParticleRenderer() = default;

Image ParticleRenderer::render(const ParticleScene& scene, const Camera& camera, int width,
                               int height, int supersample) {
  return impl_->render(scene, camera, width, height, supersample);
}

void ParticleRenderer::upload(const ParticleScene& scene) {
  impl_->upload(scene);
}

void ParticleRenderer::draw(const Camera& camera, int width, int height, double pixelScale) {
  impl_->draw(camera, width, height, pixelScale);
}

}  // namespace granular::render
