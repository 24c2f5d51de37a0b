// The private native module gridwalk._core. The public API is the Python
// package gridwalk (core/python/gridwalk), which validates shapes and dtypes
// before calling in here; this layer checks again and never trusts sizes.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>
#include <nanobind/stl/array.h>

#include <cstdlib>
#include <string>

#include "batch.h"
#include "bind_casters.h"
#include "bindings.h"
#include "gil_release.h"
#include "build_job.h"
#include "ear_clip.h"
#include "render_job.h"
#include "adaptive_grid.h"
#include "instanced_grid.h"
#include "moved_grid.h"
#include "uniform_grid.h"

namespace nb = nanobind;
using namespace nb::literals;
using namespace gw;

namespace {

template <class T>
using In = nb::ndarray<const T, nb::c_contig, nb::device::cpu>;

template <class T>
std::vector<T> vec(const In<T>& a) { return std::vector<T>(a.data(), a.data() + a.size()); }
template <class T>
PooledVector<T> pooled(const In<T>& a) { return PooledVector<T>(a.data(), a.data() + a.size()); }

nb::dict stats_dict(const Stats& s) {
    nb::dict d;
    d["primary_rays"] = s.rays[0];
    d["shadow_rays"] = s.rays[1];
    d["secondary_rays"] = s.rays[2];
    d["rays"] = s.total_rays();
    d["prim_tests"] = s.prim_tests;
    d["mailbox_skips"] = s.mailbox_skips;
    d["cells"] = s.cells;
    return d;
}

nb::dict accel_dict(const AccelInfo& g) {
    nb::dict d;
    d["kind"] = g.kind;
    d["grids"] = g.grids;
    d["resolution"] = nb::make_tuple(g.n[0], g.n[1], g.n[2]);
    d["cells"] = g.cells;
    d["refs"] = g.refs;
    d["bytes"] = g.bytes;
    d["build_seconds"] = g.build_seconds;
    d["build_threads"] = g.build_threads;
    d["density_requested"] = g.density_requested;
    d["density_used"] = g.density_used;
    d["reduced"] = g.reduced;
    d["note"] = g.note;
    return d;
}

template <class T>
nb::ndarray<nb::numpy, T> owned(std::vector<size_t> shape) {
    size_t n = 1;
    for (size_t s : shape) n *= s;
    T* p = new T[n > 0 ? n : 1];
    nb::capsule owner(p, [](void* q) noexcept { delete[] static_cast<T*>(q); });
    return nb::ndarray<nb::numpy, T>(p, shape.size(), shape.data(), owner);
}

void check_rays(const In<float>& o, const In<float>& d, const In<float>& tmin, const In<float>& tmax) {
    if (o.ndim() != 2 || o.shape(1) != 3) throw std::invalid_argument("origins must have shape (N, 3)");
    if (d.ndim() != 2 || d.shape(1) != 3 || d.shape(0) != o.shape(0))
        throw std::invalid_argument("directions must have shape (N, 3) matching origins");
    if (tmin.size() != o.shape(0) || tmax.size() != o.shape(0))
        throw std::invalid_argument("tmin and tmax must have one value per ray");
}

}  // namespace

NB_MODULE(_core, m) {
    m.doc() = "Gridwalk native core (private: use the gridwalk package)";
    // nanobind lists every instance alive when the interpreter ends: a script
    // that exits while a daemon thread still holds a scene printed some 180
    // lines of "leaked" instances, types and functions. Developers turn the
    // list back on with GRIDWALK_LEAK_WARNINGS=1 (test01 does, on a script
    // that should leave nothing behind).
    const char* leaks = std::getenv("GRIDWALK_LEAK_WARNINGS");
    nb::set_leak_warnings(leaks != nullptr && std::string(leaks) == "1");
    install_exit_hook();   // daemon threads in native calls at exit (gil_release.h)

    bind_settings(m);
    bind_records(m);

    nb::class_<Scene>(m, "Scene")
        .def("__init__",
             [](Scene* self, In<float> vertices, In<int32_t> triangles, In<float> normals, In<int32_t> tri_mat,
                In<float> centers, In<float> radii, In<int32_t> sph_mat, In<float> cb, In<float> ca, In<float> cbr,
                In<float> car, In<int32_t> cmat, std::vector<Material> materials, std::vector<Light> lights,
                const CameraDesc& camera, Vec3 background, In<float> uvs, In<float> colors,
                std::vector<std::shared_ptr<Image>> images, std::vector<Texture> textures, const World& world,
                In<float> generated, In<float> object_coords, In<float> object_normals) {
                 std::vector<std::shared_ptr<const Image>> shared(images.begin(), images.end());
                 new (self) Scene(pooled(vertices), pooled(triangles), pooled(normals), pooled(tri_mat), vec(centers),
                                  vec(radii),
                                  vec(sph_mat), vec(cb), vec(ca), vec(cbr), vec(car), vec(cmat), std::move(materials),
                                  std::move(lights), camera, background, pooled(uvs), pooled(colors), std::move(shared),
                                  std::move(textures), world, pooled(generated),
                                  pooled(object_coords), pooled(object_normals));
             })
        .def("set_matte_keys", [](Scene& s, In<int32_t> keys, int layers) { s.set_matte_keys(vec(keys), layers); },
             "keys"_a, "layers"_a,
             "Per primitive, its `layers` matte keys (-1 none), row-major; before the scene is used (Scene(matte_keys=...))")
        .def("set_instances",
             [](Scene& s, In<int64_t> triangles, In<int32_t> meshes, In<double> matrices) {
                 const size_t n = meshes.size();
                 if (triangles.size() != 2 * n || matrices.size() != 16 * n)
                     throw std::invalid_argument("instances: triangles (I, 2), meshes (I,) and matrices (I, 4, 4) "
                                                 "must describe the same number of instances");
                 std::vector<SceneInstance> out(n);
                 for (size_t i = 0; i < n; ++i) {
                     const int64_t start = triangles.data()[2 * i], count = triangles.data()[2 * i + 1];
                     if (start < 0 || count < 0)
                         throw std::invalid_argument("instances[" + std::to_string(i) +
                                                     "]: triangle start and count must be >= 0");
                     out[i].triangle_start = size_t(start);
                     out[i].triangle_count = size_t(count);
                     out[i].mesh = meshes.data()[i];
                     std::copy(matrices.data() + 16 * i, matrices.data() + 16 * (i + 1), &out[i].matrix[0][0]);
                 }
                 s.set_instances(std::move(out));
             },
             "triangles"_a, "meshes"_a, "matrices"_a,
             "Declares copies of meshes (Scene(instance_triangles=..., instance_meshes=..., instance_matrices=...))")
        .def("moved",
             [](const Scene& s, std::vector<size_t> vertex_starts, std::vector<size_t> triangle_starts,
                std::vector<size_t> triangle_counts, std::vector<In<float>> positions, std::vector<In<float>> normals,
                std::vector<bool> flat, std::vector<In<double>> matrices, std::vector<In<double>> previous) {
                 const size_t n = vertex_starts.size();
                 if (triangle_starts.size() != n || triangle_counts.size() != n || positions.size() != n ||
                     normals.size() != n || flat.size() != n || matrices.size() != n || previous.size() != n)
                     throw std::invalid_argument("moved: one entry per move in every list");
                 std::vector<RigidMove> moves(n);
                 for (size_t i = 0; i < n; ++i) {
                     if (matrices[i].size() != 16) throw std::invalid_argument("moved: matrices must be 4 x 4");
                     moves[i].vertex_start = vertex_starts[i];
                     moves[i].triangle_start = triangle_starts[i];
                     moves[i].triangle_count = triangle_counts[i];
                     moves[i].positions = vec(positions[i]);
                     moves[i].normals = vec(normals[i]);
                     moves[i].flat = flat[i];
                     std::copy(matrices[i].data(), matrices[i].data() + 16, &moves[i].matrix[0][0]);
                     if (previous[i].size() != 0 && previous[i].size() != 16)
                         throw std::invalid_argument("moved: previous matrices must be 4 x 4 (or empty)");
                     moves[i].has_previous = previous[i].size() == 16;
                     if (moves[i].has_previous)
                         std::copy(previous[i].data(), previous[i].data() + 16, &moves[i].previous_matrix[0][0]);
                 }
                 GilRelease release;
                 return s.moved(moves);
             })
        .def("geometry",
             [](const Scene& s) {
                 const Scene::Geometry g = s.geometry();
                 auto copy = [](const auto& v, size_t width, auto tag) {
                     using T = decltype(tag);
                     auto a = owned<T>({v.size() / width, width});
                     std::copy(v.begin(), v.end(), a.data());
                     return a;
                 };
                 return nb::make_tuple(copy(*g.vertices, 3, float()), copy(*g.triangles, 3, int32_t()),
                                       copy(*g.normals, 3, float()), copy(*g.materials, 1, int32_t()));
             })
        .def_prop_ro("texture_bytes", &Scene::texture_bytes)
        .def_prop_ro("num_triangles", &Scene::num_triangles)
        .def_prop_ro("num_spheres", &Scene::num_spheres)
        .def_prop_ro("num_cylinders", &Scene::num_cones)
        .def_prop_ro("num_lights", [](const Scene& s) { return s.lights().size(); })
        .def_prop_ro("memory_bytes", &Scene::memory_bytes)
        .def_prop_ro("bounds", [](const Scene& s) {
            const Bounds& b = s.bounds();
            return nb::make_tuple(nb::make_tuple(b.lo.x, b.lo.y, b.lo.z), nb::make_tuple(b.hi.x, b.hi.y, b.hi.z));
        });

    // An image's pixels, (H, W, C) uint8 or float32 with row 0 at the top,
    // copied once into the core; textures refer to it by index.
    nb::class_<Image>(m, "Image")
        .def("__init__",
             [](Image* self, nb::ndarray<nb::c_contig, nb::device::cpu> pixels, bool srgb, const std::string& where) {
                 if (pixels.ndim() != 3) throw std::invalid_argument(where + " must have shape (H, W, C)");
                 for (size_t k = 0; k < 3; ++k)
                     if (pixels.shape(k) > size_t(std::numeric_limits<int>::max()))
                         throw std::invalid_argument(where + " has " + std::to_string(pixels.shape(k)) +
                                                     (k == 0 ? " rows" : k == 1 ? " columns" : " channels") +
                                                     ": at most 2147483647");
                 const int h = int(pixels.shape(0)), w = int(pixels.shape(1)), c = int(pixels.shape(2));
                 std::vector<uint8_t> bytes;
                 std::vector<float> floats;
                 if (pixels.dtype() == nb::dtype<uint8_t>()) {
                     const auto* p = static_cast<const uint8_t*>(pixels.data());
                     bytes.assign(p, p + pixels.size());
                 } else if (pixels.dtype() == nb::dtype<float>()) {
                     const auto* p = static_cast<const float*>(pixels.data());
                     floats.assign(p, p + pixels.size());
                 } else {
                     throw std::invalid_argument(where + " must be uint8 or float32");
                 }
                 new (self) Image(w, h, c, srgb, std::move(bytes), std::move(floats), where);
             })
        .def_prop_ro("width", &Image::width)
        .def_prop_ro("height", &Image::height)
        .def_prop_ro("channels", &Image::channels)
        .def_prop_ro("memory_bytes", &Image::memory_bytes)
        .def("pixels", [](const Image& img) {   // a copy, (H, W, C), as given
            const size_t h = size_t(img.height()), w = size_t(img.width()), c = size_t(img.channels());
            if (img.is_float()) {
                auto out = owned<float>({h, w, c});
                std::copy(img.floats().begin(), img.floats().end(), out.data());
                return nb::object(nb::cast(out));
            }
            auto out = owned<uint8_t>({h, w, c});
            std::copy(img.bytes().begin(), img.bytes().end(), out.data());
            return nb::object(nb::cast(out));
        });

    nb::class_<Accel>(m, "Accel")
        .def_prop_ro("grid", [](const Accel& a) { return accel_dict(a.info()); });

    nb::exception<BuildCancelled>(m, "BuildCancelled");
    nb::class_<CancelToken>(m, "CancelToken")
        .def(nb::init<>())
        .def("cancel", &CancelToken::cancel)
        .def_prop_ro("cancelled", &CancelToken::cancelled);

    m.def("build_accel",
          [](std::shared_ptr<Scene> scene, const RenderSettings& s, std::shared_ptr<CancelToken> cancel,
             double grid_margin) {
              GilRelease release;
              return build_accel(std::move(scene), s, cancel.get(), grid_margin);
          },
          "scene"_a, "settings"_a, "cancel"_a.none() = nb::none(), "grid_margin"_a = 0.0);
    m.def("pool_bytes", &pool_bytes, "Bytes of freed buffers the buffer pool keeps for reuse (buffer_pool.h).");
    // The viewport's grid update (UniformGrid::update), for tests: None where it does not apply.
    m.def("update_grid", [](std::shared_ptr<const Accel> previous, std::shared_ptr<const Scene> scene) {
        const auto* grid = dynamic_cast<const UniformGrid*>(previous.get());
        if (!grid) throw std::invalid_argument("update_grid: the previous structure is not a uniform grid");
        GilRelease release;
        return std::shared_ptr<const Accel>(UniformGrid::update(*grid, std::move(scene)));
    }, "previous"_a, "scene"_a);

    // The grid of a moved scene made from the grid of one of its ancestors (MovedGrid::follow), for
    // tests: None where it does not apply.
    m.def("follow_grid", [](std::shared_ptr<const Accel> ancestor, std::shared_ptr<const Scene> scene) {
        auto grid = std::dynamic_pointer_cast<const UniformGrid>(ancestor);
        if (!grid) throw std::invalid_argument("follow_grid: the ancestor's structure is not a uniform grid");
        return MovedGrid::follow(std::move(grid), std::move(scene));
    }, "ancestor"_a, "scene"_a);

    nb::class_<BuildJob>(m, "BuildJob")
        .def(nb::init<std::shared_ptr<const Scene>, const RenderSettings&>(), "scene"_a, "settings"_a)
        .def("wait", &BuildJob::wait, "seconds"_a, nb::call_guard<GilRelease>(),
             "Wait up to `seconds` (negative: until done); True once the build has ended.")
        .def("cancel", &BuildJob::cancel)
        .def_prop_ro("cancelled", &BuildJob::cancelled)
        .def("result", &BuildJob::result, nb::call_guard<GilRelease>(),
             "The structure; raises the build's error (BuildCancelled after a cancel).");

    m.attr("ADAPTIVE_MAX_CELLS") = AdaptiveParams{}.max_cells;   // the adaptive grid's caps, for gridwalk.memory
    m.attr("ADAPTIVE_MAX_REFS") = AdaptiveParams{}.max_refs;
    m.attr("ADAPTIVE_CROWDED_REFS") = AdaptiveParams{}.crowded_refs;   // a crowded root's allowance
    m.attr("ADAPTIVE_CROWDED_REFS_PER_PRIM") = AdaptiveParams{}.crowded_refs_per_prim;
    m.attr("INSTANCING_AUTO_TRIANGLES") = InstancedGrid::kAutoTriangles;   // for gridwalk.memory

    m.def("uniform_grid_budget",
          [](uint64_t prims, double density, uint64_t max_cells) {
              const GridBudget b = uniform_grid_budget(prims, density, max_cells, GridParams{}.max_refs);
              return nb::make_tuple(b.cells, b.refs);
          },
          "prims"_a, "density"_a, "max_cells"_a,
          "The most (cells, primitive references) a uniform grid of this size and density holds.");

    m.def("intersect",
          [](std::shared_ptr<Accel> accel, In<float> o, In<float> d, In<float> tmin, In<float> tmax,
             const RenderSettings& s, bool spawned) {
              check_rays(o, d, tmin, tmax);
              validate_settings(s);
              const size_t n = o.shape(0);
              auto t = owned<float>({n});
              auto prim = owned<int32_t>({n});
              auto kind = owned<int32_t>({n});
              auto u = owned<float>({n});
              auto v = owned<float>({n});
              auto nrm = owned<float>({n, 3});
              const BatchOut out{t.data(), prim.data(), kind.data(), u.data(), v.data(), nrm.data()};
              Stats st;
              {
                  GilRelease release;
                  st = intersect_batch(*accel, RayBatch{o.data(), d.data(), tmin.data(), tmax.data(), n, spawned}, s,
                                       out);
              }
              return nb::make_tuple(t, prim, kind, u, v, nrm, stats_dict(st));
          });

    m.def("occluded",
          [](std::shared_ptr<Accel> accel, In<float> o, In<float> d, In<float> tmin, In<float> tmax,
             const RenderSettings& s, bool spawned) {
              check_rays(o, d, tmin, tmax);
              validate_settings(s);
              const size_t n = o.shape(0);
              auto hit = owned<uint8_t>({n});
              Stats st;
              {
                  GilRelease release;
                  st = occluded_batch(*accel, RayBatch{o.data(), d.data(), tmin.data(), tmax.data(), n, spawned}, s,
                                      hit.data());
              }
              return nb::make_tuple(hit, stats_dict(st));
          });

    m.def("ear_clip",
          [](In<double> xy) {
              if (xy.ndim() != 2 || xy.shape(1) != 2) throw std::invalid_argument("ear_clip: points must have shape (N, 2)");
              std::vector<int64_t> tri;
              {
                  GilRelease release;
                  tri = ear_clip(xy.data(), xy.shape(0));
              }
              auto out = owned<int64_t>({tri.size() / 3, 3});
              std::copy(tri.begin(), tri.end(), out.data());
              return out;
          },
          "xy"_a, "Triangles (N - 2, 3) of corner indices covering the counter-clockwise polygon xy (ear_clip.h).");

    m.def("spawn_origins",
          [](std::shared_ptr<Accel> accel, In<float> o, In<float> d, In<float> t, In<int32_t> prim, In<float> u,
             In<float> v, In<float> new_d) {
              if (o.ndim() != 2 || o.shape(1) != 3) throw std::invalid_argument("origins must have shape (N, 3)");
              const size_t n = o.shape(0);
              if (d.size() != 3 * n || t.size() != n || prim.size() != n || u.size() != n || v.size() != n ||
                  new_d.size() != 3 * n)
                  throw std::invalid_argument("spawn_origins: arrays must describe the same N rays");
              auto out = owned<float>({n, 3});
              {
                  GilRelease release;
                  spawn_batch(*accel, o.data(), d.data(), t.data(), prim.data(), u.data(), v.data(), new_d.data(), n,
                              out.data());
              }
              return out;
          });

    // The camera's own rays through image positions (px, py) in pixels from
    // the top-left corner, lens sample (lu, lv): (origins, directions, tmin, tmax).
    m.def("camera_rays", [](const CameraDesc& desc, In<float> px, In<float> py, float lu, float lv) {
        validate_camera(desc);
        if (px.size() != py.size()) throw std::invalid_argument("px and py must have the same length");
        const Camera cam(desc);
        const size_t n = px.size();
        auto o = owned<float>({n, 3}), d = owned<float>({n, 3});
        auto tmin = owned<float>({n}), tmax = owned<float>({n});
        for (size_t i = 0; i < n; ++i) {
            const Ray r = cam.generate(px.data()[i], py.data()[i], lu, lv);
            for (int k = 0; k < 3; ++k) {
                o.data()[3 * i + k] = r.o[k];
                d.data()[3 * i + k] = r.d[k];
            }
            tmin.data()[i] = r.tmin;
            tmax.data()[i] = r.tmax;
        }
        return nb::make_tuple(o, d, tmin, tmax);
    }, "camera"_a, "px"_a, "py"_a, "lu"_a = 0.5f, "lv"_a = 0.5f);

    nb::class_<RenderJob>(m, "RenderJob")
        .def(nb::init<std::shared_ptr<const Accel>, const RenderSettings&>())
        .def(nb::init<std::shared_ptr<const Accel>, const RenderSettings&, const CameraDesc&>())
        .def("start", &RenderJob::start)
        .def("poll", [](RenderJob& j) {
            std::vector<std::tuple<int, int, int, int>> out;
            for (const Tile& t : j.poll()) out.emplace_back(t.x, t.y, t.w, t.h);
            return out;
        })
        .def("cancel", &RenderJob::cancel, nb::call_guard<GilRelease>())
        .def("wait", &RenderJob::wait, nb::call_guard<GilRelease>())
        .def("wait_for", &RenderJob::wait_for, "seconds"_a, nb::call_guard<GilRelease>(),
             "Block until another tile is finished, the job ends, or `seconds` pass; True once finished.")
        .def_prop_ro("finished", &RenderJob::finished)
        .def_prop_ro("started", &RenderJob::started)
        .def_prop_ro("cancelled", &RenderJob::cancelled)
        .def_prop_ro("tiles_done", &RenderJob::tiles_done)
        .def_prop_ro("tiles_total", &RenderJob::tiles_total)
        .def_prop_ro("elapsed", &RenderJob::elapsed)
        .def_prop_ro("stats", [](const RenderJob& j) { return stats_dict(j.stats()); })
        .def_ro("width", &RenderJob::width)
        .def_ro("height", &RenderJob::height)
        .def_prop_ro("area", [](const RenderJob& j) { return std::make_tuple(j.area.x, j.area.y, j.area.w, j.area.h); })
        .def_prop_ro("rgba", [](RenderJob& j) {
            return nb::ndarray<nb::numpy, float, nb::ndim<3>>(j.rgba.data(), {size_t(j.area.h), size_t(j.area.w), 4});
        }, nb::rv_policy::reference_internal)
        .def_prop_ro("depth", [](RenderJob& j) {
            return nb::ndarray<nb::numpy, float, nb::ndim<2>>(j.depth.data(), {size_t(j.area.h), size_t(j.area.w)});
        }, nb::rv_policy::reference_internal)
        .def_prop_ro("normal", [](RenderJob& j) {
            return nb::ndarray<nb::numpy, float, nb::ndim<3>>(j.normal.data(), {size_t(j.area.h), size_t(j.area.w), 3});
        }, nb::rv_policy::reference_internal)
        .def_prop_ro("albedo", [](RenderJob& j) {
            return nb::ndarray<nb::numpy, float, nb::ndim<3>>(j.albedo.data(), {size_t(j.area.h), size_t(j.area.w), 3});
        }, nb::rv_policy::reference_internal)
        .def_prop_ro("holdout", [](RenderJob& j) {
            const size_t h = j.holdout.empty() ? 0 : size_t(j.area.h), w = j.holdout.empty() ? 0 : size_t(j.area.w);
            return nb::ndarray<nb::numpy, float, nb::ndim<2>>(j.holdout.data(), {h, w});
        }, nb::rv_policy::reference_internal)
        .def_prop_ro("matte_keys", [](RenderJob& j) {
            const size_t l = size_t(j.matte_layers), r = j.matte_keys.size() / std::max<size_t>(1, size_t(j.area.w) * size_t(j.area.h) * l);
            return nb::ndarray<nb::numpy, int32_t, nb::ndim<4>>(j.matte_keys.data(), {size_t(j.area.h), size_t(j.area.w), l, r});
        }, nb::rv_policy::reference_internal)
        .def_prop_ro("matte_coverage", [](RenderJob& j) {
            const size_t l = size_t(j.matte_layers), r = j.matte_coverage.size() / std::max<size_t>(1, size_t(j.area.w) * size_t(j.area.h) * l);
            return nb::ndarray<nb::numpy, float, nb::ndim<4>>(j.matte_coverage.data(), {size_t(j.area.h), size_t(j.area.w), l, r});
        }, nb::rv_policy::reference_internal);

    bind_viewport(m);   // uses Scene, RenderSettings and CameraDesc, bound above
    bind_sky(m);
}
