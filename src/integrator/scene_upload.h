// Copies a Scene's arrays into a backend's memory once, and points a SceneView at them.
#pragma once

#include <vector>

#include "src/scene/scene.h"

namespace pt {

template <typename Backend>
struct SceneBuffers {
  typename Backend::template Buffer<BvhNode> nodes;
  typename Backend::template Buffer<PrimRef> prims;
  typename Backend::template Buffer<Triangle> triangles;
  typename Backend::template Buffer<TriangleNormals> triangleNormals;
  typename Backend::template Buffer<Quad> quads;
  typename Backend::template Buffer<Sphere> spheres;
  typename Backend::template Buffer<Material> materials;
  typename Backend::template Buffer<Light> lights;
  typename Backend::template Buffer<float> lightPmf, lightCdf;
  typename Backend::template Buffer<TriangleUvs> triangleUvs;
  typename Backend::template Buffer<Texture> textures;
  typename Backend::template Buffer<vec3> texels;
  SceneView view;

  size_t Bytes() const {
    return nodes.Bytes() + prims.Bytes() + triangles.Bytes() + triangleNormals.Bytes() +
           quads.Bytes() + spheres.Bytes() + materials.Bytes() + lights.Bytes() +
           lightPmf.Bytes() + lightCdf.Bytes() + triangleUvs.Bytes() + textures.Bytes() +
           texels.Bytes();
  }
};

template <typename Backend>
void UploadScene(const Scene& scene, SceneBuffers<Backend>& b) {
  const SceneDesc& d = scene.desc;
  b.nodes.Upload(scene.nodes);
  b.prims.Upload(scene.prims);
  b.triangles.Upload(d.triangles);
  b.triangleNormals.Upload(d.triangleNormals);
  b.quads.Upload(d.quads);
  b.spheres.Upload(d.spheres);
  b.materials.Upload(d.materials);
  b.lights.Upload(scene.lights);
  b.lightPmf.Upload(scene.lightPmf);
  b.lightCdf.Upload(scene.lightCdf);
  b.triangleUvs.Upload(d.triangleUvs);
  b.textures.Upload(d.textures);
  b.texels.Upload(d.texels);

  SceneView v = HostSceneView(scene);  // counts and scalars; pointers replaced below
  v.nodes = b.nodes.Data();
  v.prims = b.prims.Data();
  v.triangles = b.triangles.Data();
  v.triangleNormals = b.triangleNormals.Data();
  v.quads = b.quads.Data();
  v.spheres = b.spheres.Data();
  v.materials = b.materials.Data();
  v.lights = b.lights.Data();
  v.lightPmf = b.lightPmf.Data();
  v.lightCdf = b.lightCdf.Data();
  v.triangleUvs = d.triangleUvs.empty() ? nullptr : b.triangleUvs.Data();
  v.textures = b.textures.Data();
  v.texels = b.texels.Data();
  b.view = v;
}

}  // namespace pt
