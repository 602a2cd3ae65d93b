// PLY meshes: ASCII, binary little- and big-endian; any order of vertex/face properties and extra properties
// (a face may carry other properties before or after its index list); polygons fan-triangulated; ".gz" files
// read through zlib. Throws prism::Error "<file>: <cause>" naming the element on malformed or truncated data.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace prism {

// What a PLY file says besides its mesh.
struct PlyDetails {
    std::vector<std::string> warnings;       // what was read past (ASCII lines with more values than declared)
    std::vector<std::string> texture_files;  // "comment TextureFile <name>" (MeshLab), as written, in order
};

// Positions always; normals (nx ny nz; computed smooth, area-weighted, when the file has none), colours (red green blue
// [alpha], uchar or float) and UVs (u v | s t | texture_u texture_v per vertex, or MeshLab's per-corner "texcoord"
// list on faces, which splits vertices at seams) when present, v flipped to glTF's downward direction. A triangle's
// material slot is its face's "texnumber" (an index into details->texture_files), else 0.
Mesh load_ply(const std::filesystem::path& path, PlyDetails* details = nullptr);

// The file as a model of `scene`: its mesh, one instance, and per texture its faces use a material showing it
// (trimmed names under the file's folder, under the scene's read rules; a missing one is an error), else the
// default material.
void add_ply_model(const std::filesystem::path& path, Scene& scene);

}  // namespace prism
