#include "harness/evaluation/ground_truth.hpp"

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <memory>
#include <stdexcept>
#include <thread>

#include "harness/pipeline/frame.hpp"
#include "harness/evaluation/image_cache.hpp"
#include "scenes/content_hash.hpp"

#ifndef VS_GROUND_TRUTH_SOURCE
#define VS_GROUND_TRUTH_SOURCE "unknown"
#endif

namespace vs {

namespace {

using dvec3 = glm::dvec3;
constexpr double kPi = 3.14159265358979323846;

struct DeviceDeleter {
  void operator()(RTCDeviceTy* d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
  void operator()(RTCSceneTy* s) const { rtcReleaseScene(s); }
};

// One Embree geometry per mesh, so a hit's geomID gives the mesh (and its albedo).
class Tracer {
 public:
  explicit Tracer(const Scene& scene) : scene_(scene) {
    device_.reset(rtcNewDevice("threads=1"));
    if (!device_) throw std::runtime_error("Embree: cannot create a device");
    rtcScene_.reset(rtcNewScene(device_.get()));
    for (const Mesh& mesh : scene.meshes) {
      if (mesh.indices.empty() || mesh.opacity <= 0.0f) continue;  // cut-out meshes are not there
      RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), mesh.positions.size()));
      for (size_t i = 0; i < mesh.positions.size(); ++i) {
        v[3 * i] = mesh.positions[i].x;
        v[3 * i + 1] = mesh.positions[i].y;
        v[3 * i + 2] = mesh.positions[i].z;
      }
      auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.indices.size() / 3));
      for (size_t i = 0; i < mesh.indices.size(); ++i) idx[i] = mesh.indices[i];
      rtcCommitGeometry(g);
      unsigned id = rtcAttachGeometry(rtcScene_.get(), g);
      rtcReleaseGeometry(g);
      if (albedo_.size() <= id) {
        albedo_.resize(id + 1);
        meshes_.resize(id + 1);
      }
      albedo_[id] = dvec3(mesh.albedo);
      meshes_[id] = &mesh;
      anyTranslucent_ = anyTranslucent_ || !mesh.isOpaque();
    }
    rtcCommitScene(rtcScene_.get());
  }

  struct Hit {
    bool hit = false;
    double t = 0;
    dvec3 normal{0};
    dvec3 albedo{0};
  };

  // Opacity of the surface at a hit (Mesh::opacityAt with the texture sampled at the hit's
  // interpolated texture coordinate, bilinear and repeating as on the GPU).
  double opacityAt(const RTCHit& hit) const {
    const Mesh& mesh = *meshes_[hit.geomID];
    if (mesh.alphaTexture < 0 || size_t(mesh.alphaTexture) >= scene_.alphaTextures.size() ||
        mesh.uvs.size() != mesh.positions.size())
      return mesh.opacityAt(1.0f);
    const uint32_t* tri = &mesh.indices[size_t(hit.primID) * 3];
    glm::vec2 uv = (1.0f - hit.u - hit.v) * mesh.uvs[tri[0]] + hit.u * mesh.uvs[tri[1]] + hit.v * mesh.uvs[tri[2]];
    return mesh.opacityAt(scene_.alphaTextures[size_t(mesh.alphaTexture)].sample(uv));
  }
  // A texel of no opacity the camera sees through (MASK cut out, BLEND alpha 0), as the G buffer.
  bool cutOut(const RTCHit& hit) const {
    const Mesh& mesh = *meshes_[hit.geomID];
    return mesh.alphaTexture >= 0 && opacityAt(hit) <= 0.0;
  }

  Hit intersect(dvec3 origin, dvec3 dir, double tfar) const {
    RTCRayHit rh{};
    double tnear = 0.0;
    for (int cut = 0; cut < 1000000; ++cut) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      setRay(rh.ray, origin, dir, tnear, tfar);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(rtcScene_.get(), &context, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || !cutOut(rh.hit)) break;
      double t = rh.ray.tfar;
      tnear = std::max(double(std::nextafter(float(t), std::numeric_limits<float>::infinity())), t * (1.0 + 1e-6));
    }
    Hit h;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.hit = true;
    h.t = rh.ray.tfar;
    dvec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    double len = glm::length(n);
    h.normal = len > 0 ? n / len : dvec3(0, 1, 0);
    if (glm::dot(h.normal, dir) > 0) h.normal = -h.normal;  // two-sided, facing the eye
    h.albedo = rh.hit.geomID < albedo_.size() ? albedo_[rh.hit.geomID] : dvec3(0.8);
    return h;
  }

  // Transmittance from origin along dir up to tfar: the product over every surface crossed (0 at
  // the first opaque one), found by walking the hits in order (any-hit with exact ordering).
  dvec3 transmittance(dvec3 origin, dvec3 dir, double tfar) const {
    if (!anyTranslucent_) return occluded(origin, dir, tfar) ? dvec3(0.0) : dvec3(1.0);
    dvec3 T(1.0);
    double t = 0.0;
    for (int crossings = 0; crossings < 1000000; ++crossings) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      RTCRayHit rh{};
      setRay(rh.ray, origin, dir, t, tfar);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(rtcScene_.get(), &context, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      const Mesh& mesh = *meshes_[rh.hit.geomID];
      T *= dvec3(1.0) - opacityAt(rh.hit) * (dvec3(1.0) - dvec3(mesh.transmittanceColor));
      if (T == dvec3(0.0)) break;
      // Step past this hit: the next float after it along the ray (coplanar layers each count once
      // only when they are apart by more than that).
      double hitT = rh.ray.tfar;
      t = std::nextafter(float(hitT), std::numeric_limits<float>::infinity());
      t = std::max(t, hitT * (1.0 + 1e-6));
      if (t >= tfar) break;
    }
    return T;
  }

  bool occluded(dvec3 origin, dvec3 dir, double tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    setRay(ray, origin, dir, 0.0, tfar);
    rtcOccluded1(rtcScene_.get(), &context, &ray);
    return ray.tfar < 0.0f;
  }

 private:
  static void setRay(RTCRay& r, dvec3 o, dvec3 d, double tnear, double tfar) {
    r.org_x = float(o.x);
    r.org_y = float(o.y);
    r.org_z = float(o.z);
    r.dir_x = float(d.x);
    r.dir_y = float(d.y);
    r.dir_z = float(d.z);
    r.tnear = float(tnear);
    r.tfar = tfar > 3e38 ? std::numeric_limits<float>::infinity() : float(tfar);
    r.mask = 0xFFFFFFFFu;
    r.flags = 0;
    r.time = 0;
  }

  const Scene& scene_;
  std::unique_ptr<RTCDeviceTy, DeviceDeleter> device_;
  std::unique_ptr<RTCSceneTy, SceneDeleter> rtcScene_;
  std::vector<dvec3> albedo_;
  std::vector<const Mesh*> meshes_;
  bool anyTranslucent_ = false;
};

struct LightModel {
  const Scene& scene;
  dvec3 position, direction, radiance;  // radiance: colour * intensity
  double cosOuter, cosInner, sigmaT;

  explicit LightModel(const Scene& s)
      : scene(s),
        position(s.light.position),
        direction(glm::normalize(dvec3(s.light.direction))),
        radiance(dvec3(s.light.color) * double(s.light.intensity) * (isAreaLight(s.light.type) ? double(s.light.area()) : 1.0)),
        cosOuter(std::cos(glm::radians(double(s.light.spotOuterDeg)))),
        cosInner(std::cos(glm::radians(double(s.light.spotInnerDeg)))),
        sigmaT(s.medium.sigmaT()) {}

  // Cosine emission of an area light towards unit direction l (from the light).
  double areaEmission(dvec3 l) const {
    double c = glm::dot(l, direction);
    return scene.light.twoSided ? std::fabs(c) : std::max(c, 0.0);
  }
  // L_in(x) without visibility, exactly as common.glsl's lightIncident() (area lights: their
  // centre as a cosine-lobed point light, the surface term's model).
  dvec3 incident(dvec3 x) const {
    if (scene.light.type == LightType::Directional) return radiance;
    dvec3 d = x - position;
    double r2 = std::max(glm::dot(d, d), 1e-12);
    double r = std::sqrt(r2);
    dvec3 L = radiance * (std::exp(-sigmaT * r) / r2);
    bool lobe = isAreaLight(scene.light.type) || (scene.light.type == LightType::Point && scene.light.cosineLobe);
    if (lobe) L *= areaEmission(d / r);
    if (scene.light.type == LightType::Spot) {
      double c = glm::dot(d / r, direction);
      L *= std::clamp((c - cosOuter) / std::max(cosInner - cosOuter, 1e-6), 0.0, 1.0);
    }
    return L;
  }
  dvec3 travelDir(dvec3 x) const {
    if (scene.light.type == LightType::Directional) return direction;
    dvec3 d = x - position;
    double len = glm::length(d);
    return len > 1e-20 ? d / len : direction;
  }
  // The point the light comes from as seen from x (far away along -direction for directional lights).
  dvec3 source(dvec3 x, double reach) const {
    return scene.light.type == LightType::Directional ? x - direction * reach : position;
  }
  // Exact visibility of the light from x: 0 behind opaque geometry, the transmittance of the
  // semi-transparent surfaces crossed otherwise.
  dvec3 visible(const Tracer& tracer, dvec3 x) const {
    if (scene.light.type == LightType::Directional) return tracer.transmittance(x, -direction, 1e30);
    dvec3 d = position - x;
    double r = glm::length(d);
    if (r < 1e-12) return dvec3(1.0);
    return tracer.transmittance(x, d / r, r * (1.0 - 1e-6));
  }
  double phase(double cosTheta) const {
    if (scene.medium.phase != Phase::HenyeyGreenstein) return 1.0 / (4.0 * kPi);
    double g = scene.medium.g;
    double denom = std::max(1.0 + g * g - 2.0 * g * std::clamp(cosTheta, -1.0, 1.0), 1e-12);
    return (1.0 - g * g) / (4.0 * kPi * denom * std::sqrt(denom));
  }
};

// Volume data in double precision: optical depth by Simpson's rule with 4 intervals per voxel
// side along each box's segment (the trilinear density is smooth inside each voxel, so this is
// quadrature at voxel resolution).
struct VolumeModel {
  const std::vector<Volume>& volumes;
  explicit VolumeModel(const Scene& s) : volumes(s.volumes) {}
  bool empty() const { return volumes.empty(); }

  // rgb sigma_s of the volumes at x.
  dvec3 scattering(dvec3 x) const {
    dvec3 c(0.0);
    for (const Volume& v : volumes) c += double(v.densityAt(glm::vec3(x))) * v.densityScale * dvec3(v.sigmaS);
    return c;
  }

  // rgb optical depth between a and b.
  dvec3 opticalDepth(dvec3 a, dvec3 b) const {
    dvec3 total(0.0);
    dvec3 d = b - a;
    double len = glm::length(d);
    if (len <= 0.0) return dvec3(0.0);
    for (const Volume& v : volumes) {
      double t0 = 0.0, t1 = 1.0;
      for (int k = 0; k < 3; ++k) {
        if (std::fabs(d[k]) < 1e-300) {
          if (a[k] < v.boxLo[k] || a[k] > v.boxHi[k]) t1 = -1.0;
          continue;
        }
        double ta = (v.boxLo[k] - a[k]) / d[k], tb = (v.boxHi[k] - a[k]) / d[k];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      if (t1 <= t0) continue;
      glm::dvec3 voxel = (dvec3(v.boxHi) - dvec3(v.boxLo)) / dvec3(v.dims[0], v.dims[1], v.dims[2]);
      double h = std::min({voxel.x, voxel.y, voxel.z}) / 4.0;
      int n = std::max(2, int(std::ceil((t1 - t0) * len / h)));
      n += n & 1;  // Simpson needs an even count
      double dt = (t1 - t0) / n, sum = 0.0;
      for (int i = 0; i <= n; ++i) {
        double w = (i == 0 || i == n) ? 1.0 : (i & 1) ? 4.0 : 2.0;
        sum += w * double(v.densityAt(glm::vec3(a + d * (t0 + i * dt))));
      }
      total += sum * dt / 3.0 * len * v.densityScale * dvec3(v.sigmaT());
    }
    return total;
  }
};

uint32_t hash32(uint32_t v) {
  v ^= v >> 16;
  v *= 0x7feb352dU;
  v ^= v >> 15;
  v *= 0x846ca68bU;
  v ^= v >> 16;
  return v;
}

}  // namespace

std::string groundTruthUnsupported(const Scene& scene) {
  if (scene.light.hasTexture()) return "the exact-visibility ground truth does not model light textures";
  return "";
}

namespace {

// The exact-visibility integral of one scene at one size, pixel by pixel (any thread).
class GroundTruthRenderer {
 public:
  GroundTruthRenderer(const Scene& scene, const GroundTruthOptions& options)
      : scene_(scene), options_(options), tracer_(scene), light_(scene), volumes_(scene) {
    const int W = options.width, H = options.height;
    const Camera& cam = scene.camera;
    glm::dmat4 viewProj = glm::dmat4(cameraProjection(cam, float(W) / float(std::max(H, 1)))) *
                          glm::dmat4(cameraView(cam));
    inverse_ = glm::inverse(viewProj);
    eye_ = dvec3(cam.position);
    forward_ = glm::normalize(dvec3(cam.target) - eye_);
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    surfaceOffset_ = 1e-5 * std::max(1.0, glm::length(dvec3(hi) - dvec3(lo)));
    sigmaS_ = scene.medium.sigmaS;
    sigmaT_ = scene.medium.sigmaT();
    reach_ = 4.0 * std::max(1.0, glm::length(dvec3(hi) - dvec3(lo))) + glm::length(dvec3(hi) + dvec3(lo));
    // Area lights: lightGrid^2 stratified samples per camera-ray sample.
    isArea_ = isAreaLight(scene.light.type);
    lightGrid_ = std::max(1, int(std::lround(std::sqrt(double(std::max(options.lightSamples, 1))))));
    lightSamples_ = lightGrid_ * lightGrid_;
    areaWeight_ = dvec3(scene.light.color) * double(scene.light.intensity) * double(scene.light.area()) /
                  double(lightSamples_);
  }

  // L_s and L of pixel (x, y) (row 0 = top) into `out`.
  void renderPixel(int x, int y, GroundTruth& out) const {
    const int W = options_.width, H = options_.height;
    // The pixel centre's ray, as the GPU's G-buffer sky pass computes it.
    glm::dvec4 p = inverse_ * glm::dvec4((x + 0.5) / W * 2.0 - 1.0, (H - 1 - y + 0.5) / H * 2.0 - 1.0, 1.0, 1.0);
    dvec3 dir = glm::normalize(dvec3(p) / p.w - eye_);
    double farDist = scene_.camera.farZ / std::max(glm::dot(dir, forward_), 1e-6);
    Tracer::Hit hit = firstHitBeyondNear(dir, farDist);
    double d = hit.hit ? hit.t : farDist;
    dvec3 viewDepth(0.0);  // optical depth of the volumes along the camera ray
    dvec3 Ls(0.0);
    if (sigmaS_ > 0.0 || !volumes_.empty()) Ls = inscatter(dir, d, x, y, viewDepth);
    dvec3 surface = hit.hit ? surfaceRadiance(hit, dir, d) : dvec3(0.0);
    dvec3 L = surface * glm::exp(-sigmaT_ * d - viewDepth) + Ls;
    for (int c = 0; c < 3; ++c) {
      out.inscatter.at(x, y)[c] = float(Ls[c]);
      out.final.at(x, y)[c] = float(L[c]);
    }
  }

 private:
  // The rasterizer clips at the near plane: nothing closer than near counts as a hit.
  Tracer::Hit firstHitBeyondNear(dvec3 dir, double farDist) const {
    Tracer::Hit hit = tracer_.intersect(eye_, dir, farDist);
    double nearDist = scene_.camera.nearZ / std::max(glm::dot(dir, forward_), 1e-6);
    while (hit.hit && hit.t < nearDist) {
      Tracer::Hit further = tracer_.intersect(eye_ + dir * (hit.t + surfaceOffset_), dir, farDist - hit.t);
      if (!further.hit) return further;
      further.t += hit.t + surfaceOffset_;
      hit = further;
    }
    return hit;
  }

  // Transmittance of the volumes from x towards the light.
  dvec3 lightTransmittance(dvec3 x) const {
    return volumes_.empty() ? dvec3(1.0) : glm::exp(-volumes_.opticalDepth(x, light_.source(x, reach_)));
  }

  // L_s over [0, d] of the ray, with stratified samples, equiangular from point and spot lights (the
  // weight r^2 cancels L_in's 1/r^2, so rays passing close to the light are integrated as well as
  // the rest). Adds the volumes' optical depth over the whole ray to viewDepth.
  dvec3 inscatter(dvec3 dir, double d, int x, int y, dvec3& viewDepth) const {
    const int N = std::max(options_.steps, 1);
    bool angular = scene_.light.type != LightType::Directional;
    dvec3 toLight = light_.position - eye_;
    double delta = glm::dot(toLight, dir);
    double D = std::max(glm::length(toLight - delta * dir), 1e-9 * std::max(d, 1.0));
    double thetaA = std::atan2(-delta, D), thetaB = std::atan2(d - delta, D);
    double offset = (hash32(uint32_t(x) * 73856093u ^ uint32_t(y) * 19349663u ^ options_.seed) >> 8) / 16777216.0;
    double sPrev = 0.0;
    dvec3 Ls(0.0);
    for (int i = 0; i < N; ++i) {
      double u = (i + std::fmod(offset + i * 0.61803398875, 1.0)) / N;
      double s, weight;
      if (angular) {
        s = std::clamp(delta + D * std::tan(thetaA + u * (thetaB - thetaA)), 0.0, d);
        weight = (thetaB - thetaA) * (D * D + (s - delta) * (s - delta)) / (D * N);
      } else {
        s = u * d;
        weight = d / N;
      }
      dvec3 xs = eye_ + dir * s;
      dvec3 scattering(sigmaS_);
      if (!volumes_.empty()) {
        viewDepth += volumes_.opticalDepth(eye_ + dir * sPrev, xs);
        sPrev = s;
        scattering += volumes_.scattering(xs);
      }
      if (scattering == dvec3(0.0)) continue;
      if (isArea_) {
        Ls += weight * scattering * glm::exp(-sigmaT_ * s - viewDepth) * areaLightIncident(xs, dir, offset, i) *
              areaWeight_;
        continue;
      }
      dvec3 V = light_.visible(tracer_, xs);
      if (V == dvec3(0.0)) continue;
      Ls += weight * scattering * glm::exp(-sigmaT_ * s - viewDepth) * lightTransmittance(xs) * V *
            light_.phase(glm::dot(light_.travelDir(xs), -dir)) * light_.incident(xs);
    }
    if (!volumes_.empty()) viewDepth += volumes_.opticalDepth(eye_ + dir * sPrev, eye_ + dir * d);
    return Ls;
  }

  // An area light's phase-weighted incident light at xs (before areaWeight): stratified, per-pixel
  // jittered points on the light, each with exact visibility.
  dvec3 areaLightIncident(dvec3 xs, dvec3 dir, double offset, int i) const {
    dvec3 sum(0.0);
    for (int k = 0; k < lightSamples_; ++k) {
      double lu = (k % lightGrid_ + std::fmod(offset + 0.38196601125 * (k + 1) * (i + 1), 1.0)) / lightGrid_;
      double lv = (k / lightGrid_ + std::fmod(offset * 1.61803398875 + 0.7548776662 * (k + 1), 1.0)) / lightGrid_;
      dvec3 p = dvec3(scene_.light.samplePoint(float(std::min(lu, 1.0 - 1e-7)), float(std::min(lv, 1.0 - 1e-7))));
      dvec3 d = xs - p;
      double r2 = std::max(glm::dot(d, d), 1e-12), r = std::sqrt(r2);
      dvec3 l = d / r;
      double emission = light_.areaEmission(l);
      if (emission <= 0.0) continue;
      dvec3 V = tracer_.transmittance(xs, -l, r * (1.0 - 1e-6));
      sum += V * (emission * std::exp(-sigmaT_ * r) / r2 * light_.phase(glm::dot(l, -dir)));
    }
    return sum;
  }

  // Diffuse reflection of the light at the surface the ray hits at distance d.
  dvec3 surfaceRadiance(const Tracer::Hit& hit, dvec3 dir, double d) const {
    dvec3 xs = eye_ + dir * d;
    dvec3 toLight = -light_.travelDir(xs);
    double cosine = std::max(glm::dot(hit.normal, toLight), 0.0);
    if (cosine <= 0.0) return dvec3(0.0);
    return hit.albedo / kPi * light_.incident(xs) * cosine * lightTransmittance(xs) *
           light_.visible(tracer_, xs + hit.normal * surfaceOffset_);
  }

  const Scene& scene_;
  const GroundTruthOptions& options_;
  Tracer tracer_;
  LightModel light_;
  VolumeModel volumes_;
  glm::dmat4 inverse_;
  dvec3 eye_, forward_;
  double surfaceOffset_ = 0.0, sigmaS_ = 0.0, sigmaT_ = 0.0, reach_ = 0.0;
  bool isArea_ = false;
  int lightGrid_ = 1, lightSamples_ = 1;
  dvec3 areaWeight_{0.0};
};

}  // namespace

GroundTruth renderGroundTruth(const Scene& scene, const GroundTruthOptions& options,
                              const std::function<void(int, int)>& progress) {
  std::string why = groundTruthUnsupported(scene);
  if (!why.empty()) throw std::runtime_error(why);
  auto start = std::chrono::steady_clock::now();
  const GroundTruthRenderer renderer(scene, options);
  const int W = options.width, H = options.height;
  GroundTruth out;
  out.inscatter = Image(W, H);
  out.final = Image(W, H);
  // Rows are handed out one at a time to every thread; the calling thread reports progress.
  std::atomic<int> nextRow{0}, rowsDone{0};
  auto worker = [&](bool reports) {
    for (int y = nextRow++; y < H; y = nextRow++) {
      for (int x = 0; x < W; ++x) renderer.renderPixel(x, y, out);
      int done = ++rowsDone;
      if (reports && progress) progress(done, H);
    }
  };
  int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, false);
  worker(true);
  for (auto& t : pool) t.join();
  out.computeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

GroundTruth obtainGroundTruth(const Scene& scene, const GroundTruthOptions& options, const std::string& cacheDir,
                              const std::function<void(int, int)>& progress) {
  std::string keyText = "vshadow-ground-truth-v1\n" + scene.contentHash + "\n" + std::to_string(options.width) + "x" +
                        std::to_string(options.height) + "\nsteps=" + std::to_string(options.steps) +
                        "\nlight_samples=" + std::to_string(options.lightSamples) +
                        "\nseed=" + std::to_string(options.seed) + "\nsource=" + VS_GROUND_TRUTH_SOURCE;
  ContentHasher hasher;
  hasher.addBlock(keyText);
  const std::string key = hasher.hex();
  const std::string base = (std::filesystem::path(cacheDir) / (scene.name + "-exact-" + key)).string();
  if (auto cached = readCachedImages(base, keyText, options.width, options.height)) {
    GroundTruth truth;
    truth.inscatter = std::move(cached->inscatter);
    truth.final = std::move(cached->final);
    truth.computeMs = cached->meta.value("compute_ms", 0.0);
    truth.fromCache = true;
    truth.cacheKey = key;
    truth.cachePath = base;
    return truth;
  }
  GroundTruth truth = renderGroundTruth(scene, options, progress);
  truth.cacheKey = key;
  truth.cachePath = base;
  writeCachedImages(base, keyText, truth.inscatter, truth.final,
                    {{"scene", scene.name},
                     {"scene_source", scene.source},
                     {"width", options.width},
                     {"height", options.height},
                     {"steps", options.steps},
                     {"light_samples", options.lightSamples},
                     {"seed", options.seed},
                     {"compute_ms", truth.computeMs}});
  return truth;
}

}  // namespace vs
