// `scene3d`: the scene's meshes, each light's shape and shadow-map frustum, the camera's frustum,
// and for the picked pixel its surface point (the G-buffer's position, as `render --positions`
// writes it) with rays to stratified samples of the light, coloured blocked or free. The samples
// are those of the `raytraced` reference (shaders/shared/light_sampling.glsl, seeded per pixel), and
// each ray is tested here against the casters' triangles with its own ray-triangle test (Moller and
// Trumbore 1997), so the free weight equals `raytraced` visibility with M = rays (a test checks it).
#include <vtkActor.h>
#include <vtkAppendPolyData.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkIntArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>

#include "shared/shared.h"
#include "view_common.h"
#include "visibility/raytracer.h"

namespace shadowlab {

namespace {

enum Part { kSceneMeshes = 0, kLightShape = 1, kLightFrustum = 2, kCamera = 3, kPickedPoint = 4, kRays = 5 };

const glm::vec3 kLightRgb(1.0f, 0.85f, 0.25f), kFrustumRgb(0.95f, 0.55f, 0.2f), kCameraRgb(0.45f, 0.8f, 1.0f),
    kPickedRgb(1.0f, 0.3f, 1.0f), kFreeRgb(0.35f, 0.95f, 0.45f), kBlockedRgb(0.95f, 0.2f, 0.2f);

// Geometry of one part, with the cell arrays every part carries (so the parts append into one
// export): "part" (the Part code), "colour" (RGB bytes) and "blocked" (rays: 1 blocked, 0 free;
// -1 elsewhere).
struct PartBuilder {
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> verts, lines, polys;
    std::vector<std::array<unsigned char, 3>> vertColours, lineColours, polyColours;
    std::vector<int> vertBlocked, lineBlocked, polyBlocked;
    int part = 0;

    static std::array<unsigned char, 3> bytes(glm::vec3 c) {
        glm::vec3 b = glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f;
        return {(unsigned char)b.x, (unsigned char)b.y, (unsigned char)b.z};
    }
    vtkIdType point(glm::vec3 p) { return points->InsertNextPoint(p.x, p.y, p.z); }
    void vertex(glm::vec3 p, glm::vec3 rgb) {
        vtkIdType id = point(p);
        verts->InsertNextCell(1, &id);
        vertColours.push_back(bytes(rgb));
        vertBlocked.push_back(-1);
    }
    void line(glm::vec3 a, glm::vec3 b, glm::vec3 rgb, int blocked = -1) {
        vtkIdType ids[2] = {point(a), point(b)};
        lines->InsertNextCell(2, ids);
        lineColours.push_back(bytes(rgb));
        lineBlocked.push_back(blocked);
    }
    void polyline(const std::vector<glm::vec3>& ps, glm::vec3 rgb, bool closed) {
        for (size_t i = 0; i + 1 < ps.size() + (closed ? 1 : 0); ++i) line(ps[i], ps[(i + 1) % ps.size()], rgb);
    }
    void triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 rgb) {
        vtkIdType ids[3] = {point(a), point(b), point(c)};
        polys->InsertNextCell(3, ids);
        polyColours.push_back(bytes(rgb));
        polyBlocked.push_back(-1);
    }
    // VTK orders cells verts, lines, polys: the cell arrays follow that order.
    void fill(vtkPolyData* out) {
        out->SetPoints(points);
        out->SetVerts(verts);
        out->SetLines(lines);
        out->SetPolys(polys);
        vtkNew<vtkIntArray> partArray, blockedArray;
        partArray->SetName("part");
        blockedArray->SetName("blocked");
        vtkNew<vtkUnsignedCharArray> colourArray;
        colourArray->SetName("colour");
        colourArray->SetNumberOfComponents(3);
        auto add = [&](const std::vector<std::array<unsigned char, 3>>& colours, const std::vector<int>& blocked) {
            for (size_t i = 0; i < colours.size(); ++i) {
                partArray->InsertNextValue(part);
                blockedArray->InsertNextValue(blocked[i]);
                colourArray->InsertNextTypedTuple(colours[i].data());
            }
        };
        add(vertColours, vertBlocked);
        add(lineColours, lineBlocked);
        add(polyColours, polyBlocked);
        out->GetCellData()->AddArray(partArray);
        out->GetCellData()->AddArray(blockedArray);
        out->GetCellData()->AddArray(colourArray);
    }
};

// Moller and Trumbore 1997: does the segment origin + s dir, s in (0, tfar), cross the triangle?
bool segmentHits(const WorldTriangle& tri, glm::vec3 origin, glm::vec3 dir, float tfar) {
    glm::vec3 e1 = tri.b - tri.a, e2 = tri.c - tri.a;
    glm::vec3 p = glm::cross(dir, e2);
    float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-12f) return false;  // parallel to the triangle's plane
    float inv = 1.0f / det;
    glm::vec3 s = origin - tri.a;
    float u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) return false;
    glm::vec3 q = glm::cross(s, e1);
    float v = glm::dot(dir, q) * inv;
    if (v < 0.0f || u + v > 1.0f) return false;
    float t = glm::dot(e2, q) * inv;
    return t > 0.0f && t < tfar;
}

// Shape of a light: its outline in its plane, its centre and the direction it faces.
void addLightShape(PartBuilder& b, const Light& light, float arrowLength) {
    glm::vec3 c = light.position, r = light.isPoint() ? glm::vec3(1, 0, 0) : light.right(), u = light.up;
    if (light.isPoint()) {
        float s = arrowLength * 0.15f;
        b.line(c - s * glm::vec3(1, 0, 0), c + s * glm::vec3(1, 0, 0), kLightRgb);
        b.line(c - s * glm::vec3(0, 1, 0), c + s * glm::vec3(0, 1, 0), kLightRgb);
        b.line(c - s * glm::vec3(0, 0, 1), c + s * glm::vec3(0, 0, 1), kLightRgb);
    } else if (light.shape == LightShape::Square) {
        float h = light.size * 0.5f;
        b.polyline({c - h * r - h * u, c + h * r - h * u, c + h * r + h * u, c - h * r + h * u}, kLightRgb, true);
    } else {
        // Disk (and a sphere's silhouette disk, sampled as the disk facing the light's direction).
        auto circle = [&](glm::vec3 x, glm::vec3 y) {
            std::vector<glm::vec3> ps;
            for (int i = 0; i < 48; ++i) {
                float a = float(i) / 48.0f * 6.2831853f;
                ps.push_back(c + light.size * (std::cos(a) * x + std::sin(a) * y));
            }
            b.polyline(ps, kLightRgb, true);
        };
        circle(r, u);
        if (light.shape == LightShape::Sphere) {
            circle(r, light.direction);
            circle(u, light.direction);
        }
    }
    b.vertex(c, kLightRgb);
    b.line(c, c + light.direction * arrowLength, kLightRgb);
}

// The shadow map's frustum: 8 corners at the near and far planes of the fitted light view.
void addLightFrustum(PartBuilder& b, const LightView& view) {
    glm::mat4 worldFromView = glm::inverse(view.viewFromWorld);
    auto corner = [&](float z, float sx, float sy) {
        return glm::vec3(worldFromView * glm::vec4(sx * z * view.tanHalfFov, sy * z * view.tanHalfFov, -z, 1.0f));
    };
    for (float z : {view.nearZ, view.farZ})
        b.polyline({corner(z, -1, -1), corner(z, 1, -1), corner(z, 1, 1), corner(z, -1, 1)}, kFrustumRgb, true);
    for (float sx : {-1.0f, 1.0f})
        for (float sy : {-1.0f, 1.0f}) b.line(corner(view.nearZ, sx, sy), corner(view.farZ, sx, sy), kFrustumRgb);
}

// The camera: apex and the image rectangle at the distance of its target.
void addCamera(PartBuilder& b, const Camera& camera, float aspect) {
    glm::mat4 worldFromView = glm::inverse(camera.viewFromWorld());
    float d = glm::length(camera.target - camera.position);
    float h = d * std::tan(glm::radians(camera.fovYDegrees) * 0.5f), w = h * aspect;
    auto at = [&](float x, float y) { return glm::vec3(worldFromView * glm::vec4(x, y, -d, 1.0f)); };
    std::vector<glm::vec3> rect = {at(-w, -h), at(w, -h), at(w, h), at(-w, h)};
    b.polyline(rect, kCameraRgb, true);
    for (const glm::vec3& p : rect) b.line(camera.position, p, kCameraRgb);
    b.line(at(-w * 0.3f, h * 1.05f), at(0, h * 1.3f), kCameraRgb);  // the "up" notch
    b.line(at(0, h * 1.3f), at(w * 0.3f, h * 1.05f), kCameraRgb);
    b.vertex(camera.position, kCameraRgb);
}

vtkSmartPointer<vtkActor> partActor(vtkAlgorithmOutput* port, float lineWidth, bool lit) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(port);
    mapper->SetScalarModeToUseCellFieldData();
    mapper->SelectColorArray("colour");
    mapper->SetColorModeToDirectScalars();
    mapper->ScalarVisibilityOn();
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetLineWidth(lineWidth);
    actor->GetProperty()->SetPointSize(lineWidth * 2.0f);
    if (!lit) actor->GetProperty()->LightingOff();
    return actor;
}

void build(ViewContext& ctx, ViewResult& result) {
    const Renderer& renderer = ctx.renderer;
    const Scene& scene = ctx.scene;
    const double t = renderer.time();
    Bounds bounds = scene.bounds(t);
    const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.hi - bounds.lo);

    auto makeSource = [](std::function<void(PartBuilder&)> fill, int part) {
        vtkNew<FunctionSource> source;
        source->SetGenerator([fill, part](vtkPolyData* out) {
            PartBuilder b;
            b.part = part;
            fill(b);
            b.fill(out);
        });
        return vtkSmartPointer<FunctionSource>(source);
    };

    // Scene meshes, coloured by albedo.
    // (Sources keep copies of what they draw: a kept VtkOffscreen may re-run them after the scene went.)
    std::vector<WorldTriangle> triangles = worldTriangles(scene, t, false);
    std::vector<glm::vec3> albedos;
    for (const Object& o : scene.objects) albedos.push_back(o.albedo);
    auto meshes = makeSource(
        [triangles, albedos](PartBuilder& b) {
            for (const WorldTriangle& tri : triangles) b.triangle(tri.a, tri.b, tri.c, albedos[size_t(tri.object)]);
        },
        kSceneMeshes);
    std::vector<Light> lights;
    std::vector<LightView> views;
    for (const LightState* l : renderer.lights()) {
        lights.push_back(l->light);
        if (l->light.castsShadows) views.push_back(l->view);
    }
    auto lightShapes = makeSource(
        [lights, diagonal](PartBuilder& b) {
            for (const Light& l : lights) addLightShape(b, l, 0.08f * diagonal);
        },
        kLightShape);
    auto frusta = makeSource(
        [views](PartBuilder& b) {
            for (const LightView& v : views) addLightFrustum(b, v);
        },
        kLightFrustum);
    const Camera camera = renderer.camera();
    const float aspect = float(renderer.width()) / float(renderer.height());
    auto cameraSource = makeSource([camera, aspect](PartBuilder& b) { addCamera(b, camera, aspect); }, kCamera);

    // The picked pixel: its point from the G-buffer and its rays to the light samples.
    nlohmann::json data;
    std::string pixelLine;
    vtkSmartPointer<FunctionSource> picked, rays;
    std::optional<glm::vec3> point;
    if (ctx.request.pixel) {
        const glm::ivec2 px = *ctx.request.pixel;
        const Image positions = renderer.positions();
        const Image normals = renderer.normals();
        glm::vec3 p(positions.at(px.x, px.y, 0), positions.at(px.x, px.y, 1), positions.at(px.x, px.y, 2));
        data["pixel"] = {px.x, px.y};
        if (!std::isfinite(p.x)) {
            data["point"] = nullptr;
            pixelLine = "pixel (" + std::to_string(px.x) + ", " + std::to_string(px.y) + "): background, no surface";
        } else {
            point = p;
            glm::vec3 n(normals.at(px.x, px.y, 0), normals.at(px.x, px.y, 1), normals.at(px.x, px.y, 2));
            const Light& light = ctx.light().light;
            const bool pointLight = light.isPoint();
            const uint32_t samples = pointLight ? 1u : uint32_t(ctx.request.rays);
            // As the raytraced reference: seed = hash of the pixel index, origin off the surface,
            // samples behind the receiver's tangent plane blocked without a ray.
            const uint32_t seed = shared::pcgHash(uint32_t(size_t(px.y) * size_t(renderer.width()) + size_t(px.x)));
            const float offset = shadowRayOffset(diagonal, p);
            const bool hasNormal = std::isfinite(n.x) && glm::dot(n, n) > 0.0f;
            if (hasNormal) n = glm::normalize(n);
            std::vector<WorldTriangle> casters = worldTriangles(scene, t, true);
            struct Ray {
                glm::vec3 sample;
                bool blocked;
                float weight;
            };
            std::vector<Ray> traced;
            double freeWeight = 0.0;
            int blockedCount = 0;
            for (uint32_t i = 0; i < samples; ++i) {
                glm::vec3 sample = light.position;
                float weight = 1.0f;
                if (!pointLight) {
                    glm::vec3 uvw = shared::stratifiedSample(i, samples, seed);
                    sample = shared::lightSamplePosition(light.position, light.right(), light.up, int(light.shape),
                                                         light.size, glm::vec2(uvw.x, uvw.y));
                    weight = uvw.z;
                }
                glm::vec3 toLight = sample - p;
                const bool behind = hasNormal && !shared::inFrontOfTangentPlane(p, n, sample);
                glm::vec3 side = hasNormal ? n : glm::normalize(toLight);
                glm::vec3 origin = p + offset * side;
                glm::vec3 dir = sample - origin;
                float distance = glm::length(dir);
                bool blocked = behind;
                if (!behind && distance > 0.0f && std::isfinite(distance)) {
                    dir /= distance;
                    float tfar = distance * (1.0f - 1e-5f);
                    for (const WorldTriangle& tri : casters)
                        if (segmentHits(tri, origin, dir, tfar)) {
                            blocked = true;
                            break;
                        }
                }
                if (blocked) ++blockedCount;
                else freeWeight += weight;
                traced.push_back({sample, blocked, weight});
            }
            double visibility = blockedCount == 0 ? 1.0 : blockedCount == int(samples) ? 0.0 : freeWeight;
            data["point"] = {p.x, p.y, p.z};
            data["normal"] = hasNormal ? nlohmann::json{n.x, n.y, n.z} : nlohmann::json(nullptr);
            data["rays"] = samples;
            data["blocked"] = blockedCount;
            data["free_weight"] = visibility;
            char line[320];
            std::snprintf(line, sizeof line,
                          "pixel (%d, %d) at (%.4g, %.4g, %.4g): %d of %u rays to L%d blocked (red), free %.4f",
                          px.x, px.y, p.x, p.y, p.z, blockedCount, samples, ctx.request.light, visibility);
            pixelLine = line;
            rays = makeSource(
                [traced, p](PartBuilder& b) {
                    for (const Ray& r : traced) b.line(p, r.sample, r.blocked ? kBlockedRgb : kFreeRgb, r.blocked ? 1 : 0);
                },
                kRays);
        }
        picked = makeSource(
            [point, camera](PartBuilder& b) {
                if (!point) return;
                b.vertex(*point, kPickedRgb);
                b.line(camera.position, *point, kPickedRgb);
            },
            kPickedPoint);
    }

    char head[256];
    std::snprintf(head, sizeof head, "scene3d  %s / %s, t = %.3g s: light (yellow), light frustum (orange), camera (blue)",
                  scene.name.c_str(), ctx.light().desc->id.c_str(), t);
    result.caption = head;
    if (!pixelLine.empty()) result.caption += "\n" + pixelLine;
    result.data = data;
    const double strip = addCaptionStrip(ctx.out, result.caption);

    vtkRenderer* r3 = ctx.out.addRenderer();
    r3->SetViewport(0.0, strip, 1.0, 1.0);
    r3->SetBackground(0.10, 0.11, 0.14);
    r3->SetBackground2(0.22, 0.24, 0.30);
    r3->GradientBackgroundOn();
    auto meshActor = partActor(meshes->GetOutputPort(), 1.0f, true);
    meshActor->GetProperty()->SetAmbient(0.25);
    meshActor->GetProperty()->SetDiffuse(0.75);
    r3->AddActor(meshActor);
    r3->AddActor(partActor(lightShapes->GetOutputPort(), 3.0f, false));
    r3->AddActor(partActor(frusta->GetOutputPort(), 1.5f, false));
    r3->AddActor(partActor(cameraSource->GetOutputPort(), 2.0f, false));
    if (rays) r3->AddActor(partActor(rays->GetOutputPort(), 1.5f, false));
    if (picked) r3->AddActor(partActor(picked->GetOutputPort(), 2.0f, false));
    if (point) r3->AddActor(pointMarker(*point, 0.008 * diagonal, kPickedRgb));

    // The default view looks along the scene camera's direction, orbited so that the camera's own
    // frustum and the light stand out; the request orbits and zooms from there.
    orbitSceneCamera(r3, camera, 45.0 + ctx.request.azimuth, 10.0 + ctx.request.elevation);
    vtkCamera* view = r3->GetActiveCamera();
    // Fit the scene, the lights, the camera and the picked point; frusta may reach beyond.
    Bounds fit = bounds;
    for (const Light& l : lights) {
        fit.extend(l.position - glm::vec3(l.size));
        fit.extend(l.position + glm::vec3(l.size));
    }
    fit.extend(camera.position);
    double box[6] = {fit.lo.x, fit.hi.x, fit.lo.y, fit.hi.y, fit.lo.z, fit.hi.z};
    r3->ResetCamera(box);
    view->Zoom(1.15 * ctx.request.zoom);
    r3->ResetCameraClippingRange();


    if (!ctx.request.exportPath.empty()) {
        vtkNew<vtkAppendPolyData> all;
        for (FunctionSource* s : {meshes.Get(), lightShapes.Get(), frusta.Get(), cameraSource.Get(), picked.Get(), rays.Get()})
            if (s) all->AddInputConnection(s->GetOutputPort());
        all->Update();
        writePolyData(all->GetOutput(), ctx.exportTarget(ctx.request.exportPath));
    }
}

}  // namespace

const ViewDesc& scene3dView() {
    static const ViewDesc desc = [] {
        ViewDesc d;
        d.info.name = "scene3d";
        d.info.doc = "the scene in 3D: meshes, light shapes and shadow-map frusta, the camera; with --pixel the "
                     "picked point and its rays to the light samples (red blocked, green free)";
        d.info.appliesTo = "every technique";
        d.info.exportExtension = ".vtp";
        d.build = build;
        return d;
    }();
    return desc;
}

}  // namespace shadowlab
