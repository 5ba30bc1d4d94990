// Pipeline: scene description. Native Wavefront OBJ reader behind the
// prelude's mesh_from_obj(path): large files never pass through Lua.
#pragma once

#include "scene/mesh_builder.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace lray {

/// Reads v, vt, vn and f statements (all four corner forms v, v/vt, v//vn,
/// v/vt/vn; negative = relative indices; polygons kept whole, to be fanned
/// by buildMeshData). Accepts CRLF line endings, comments and trailing
/// spaces; ignores grouping/material statements (o g s usemtl mtllib) and
/// non-surface elements (l p vp). Anything else malformed throws SceneError
/// "displayName:line: message"; nothing is dropped silently. A file larger
/// than `maxBytes` is refused before it is read (--max-file-size); one
/// whose text and arrays together would pass `memoryBytes` (what the
/// script has left of --script-memory; 0: no limit) is refused before it
/// is read or at the line where they pass it.
MeshSource loadObj(const std::string &path, const std::string &displayName,
                   uint64_t maxBytes = uint64_t{1} << 30, uint64_t memoryBytes = 0);

/// Same, from the text of an OBJ file (for tests).
MeshSource parseObj(std::string_view text, const std::string &displayName,
                    uint64_t memoryBytes = 0);

} // namespace lray
