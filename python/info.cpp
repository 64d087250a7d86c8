// glint — `glint info` as a Python dict (see info.h).
#include "python/info.h"

#include <pybind11/stl.h>

namespace py = pybind11;

namespace glint::python {

namespace {

py::list named(const std::vector<SceneInfo::Named>& items) {
  py::list out;
  for (const SceneInfo::Named& n : items)
    out.append(py::dict(py::arg("name") = n.name, py::arg("type") = n.type));
  return out;
}

py::tuple xyz(Vec3f v) { return py::make_tuple(v.x, v.y, v.z); }

}  // namespace

py::dict infoDict(const SceneInfo& info) {
  py::dict d;
  d["scene"] = info.file;
  d["warnings"] = info.warnings;
  d["meshes"] = info.meshes;
  d["triangles_stored"] = info.trianglesStored;
  d["triangles_placed"] = info.trianglesPlaced;
  d["instances"] = info.instances;
  py::list nodes;
  for (const SceneInfo::Node& n : info.nodes)
    nodes.append(py::dict(py::arg("name") = n.name, py::arg("meshes") = n.meshes));
  d["nodes"] = nodes;
  py::list objects;
  for (const SceneInfo::Object& o : info.objects) {
    py::dict object(py::arg("name") = o.name, py::arg("type") = o.type);
    if (o.type == "csg") object["leaves"] = o.leaves;
    if (o.type == "terrain") object["triangles"] = o.triangles;
    objects.append(object);
  }
  d["objects"] = objects;
  d["materials"] = named(info.materials);
  d["textures"] = info.textures;
  d["images"] = info.images;
  d["image_storage"] = info.imageDescriptions;
  d["images_in_memory_mib"] = double(info.imageBytes) / (1024.0 * 1024.0);
  d["variants"] = info.variants;
  d["variant"] = info.variant.empty() ? py::object(py::none()) : py::object(py::str(info.variant));
  d["cameras"] = named(info.cameras);
  d["camera"] = info.camera;
  d["lights"] = named(info.lights);
  py::list media;
  for (const SceneInfo::Medium& m : info.media) {
    py::list grids;
    for (const VdbGridInfo& g : m.grids)
      grids.append(py::dict(
          py::arg("name") = g.name, py::arg("type") = g.type,
          py::arg("voxel_size") = xyz(g.voxelSize), py::arg("active_voxels") = g.activeVoxels,
          py::arg("bounds") =
              g.worldBounds.empty()
                  ? py::object(py::none())
                  : py::object(py::make_tuple(xyz(g.worldBounds.lower), xyz(g.worldBounds.upper))),
          py::arg("memory_bytes") = g.memoryBytes));
    media.append(py::dict(py::arg("name") = m.name, py::arg("type") = m.type,
                          py::arg("vdb_file") = m.vdbFile.empty() ? py::object(py::none())
                                                                  : py::object(py::str(m.vdbFile)),
                          py::arg("vdb_bytes") = m.vdbBytes, py::arg("grids") = grids));
  }
  d["media"] = media;
  py::list emitters;
  for (const UnsampledEmitter& e : info.unsampledEmitters)
    emitters.append(py::dict(py::arg("instance") = e.instance, py::arg("shape") = e.shape,
                             py::arg("reason") = e.reason));
  d["unsampled_emitters"] = emitters;
  d["bounds"] = info.bounds.empty()
                    ? py::object(py::none())
                    : py::object(py::make_tuple(xyz(info.bounds.lower), xyz(info.bounds.upper)));
  d["image"] = py::dict(py::arg("width") = info.width, py::arg("height") = info.height,
                        py::arg("spp") = info.spp, py::arg("seed") = info.seed,
                        py::arg("accel") = info.accel, py::arg("integrator") = info.integrator,
                        py::arg("integrator_auto") = info.integratorAuto);
  d["animation"] =
      info.animatedNodes == 0
          ? py::object(py::none())
          : py::object(py::dict(py::arg("animated_nodes") = info.animatedNodes,
                                py::arg("start") = info.animationStart,
                                py::arg("end") = info.animationEnd,
                                py::arg("first_frame") = info.firstFrame,
                                py::arg("last_frame") = info.lastFrame, py::arg("fps") = info.fps));
  d["motion"] =
      py::dict(py::arg("moving") = info.moving, py::arg("moving_keys") = info.movingKeys,
               py::arg("deforming") = info.deforming, py::arg("deform_steps") = info.deformSteps);
  d["effects"] = info.effects;
  return d;
}

}  // namespace glint::python
