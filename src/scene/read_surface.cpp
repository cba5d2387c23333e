// Reading a surface body: a closed triangulated surface from an STL (ASCII or binary) or OBJ file, read with
// assimp, scaled and moved into place, refused where it bounds no region.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <system_error>

#include "section.hpp"

namespace mpm::scene_reading {

namespace {
/// The triangles of every mesh of the file, in the file's units; empty with `error` set when assimp cannot
/// read it.
TriangleSurface load_triangles(const std::filesystem::path& file, std::string& error) {
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices);
  TriangleSurface out;
  if (!scene) {
    error = importer.GetErrorString();
    return out;
  }
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& mesh = *scene->mMeshes[m];
    const auto base = static_cast<std::int32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
      out.vertices.emplace_back(mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z);
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines bound nothing
      out.faces.push_back({base + static_cast<std::int32_t>(face.mIndices[0]),
                           base + static_cast<std::int32_t>(face.mIndices[1]),
                           base + static_cast<std::int32_t>(face.mIndices[2])});
    }
  }
  return out;
}
}  // namespace

TriangleSurface read_surface(const Section& s, const Scene& sc, const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".stl" && extension != ".obj")
    s.fail("file", "expected an .stl (ASCII or binary) or .obj file, got " + in_quotes(file.string()));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) s.fail("file", "cannot open " + in_quotes(file.string()));
  std::string error;
  TriangleSurface surface = load_triangles(file, error);
  if (!error.empty()) s.fail("file", in_quotes(file.string()) + " cannot be read: " + shortened(error));
  weld(surface);
  if (surface.faces.empty()) s.fail("file", in_quotes(file.string()) + " holds no triangles");
  if (const auto defect = closure_defect(surface)) s.fail("file", in_quotes(file.string()) + ": " + *defect);
  const double scale = s.constant_number("scale", 1, sc.constants);
  if (!(scale > 0)) s.fail("scale", "expected a positive factor (the file's unit in metres)");
  const std::vector<double> shift =
      s.has("translate") ? s.constant_numbers("translate", 3, sc.constants) : std::vector<double>(3, 0.0);
  for (Vec<3>& v : surface.vertices) v = scale * v + Vec<3>(shift[0], shift[1], shift[2]);
  if (!(surface.volume() > 0)) s.fail("file", in_quotes(file.string()) + " encloses no volume");
  return surface;
}

}  // namespace mpm::scene_reading
