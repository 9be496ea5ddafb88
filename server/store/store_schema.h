// The table both stores keep, so that SQLite and PostgreSQL rows read the same. Metadata has its
// own columns so that listing never reads mesh content.
#pragma once

namespace tessera::server::schema {

// Bumped when the table changes; a store refuses a database written by a newer server.
inline constexpr int kVersion = 1;

// Metadata columns in the order stores bind and read them; `boundary` holds the mesh's rules code
// (rulesFromColumn in mesh_metadata.h).
inline constexpr const char* kMetadataColumns =
    "id, display_name, source_format, source_bytes, boundary, vertex_count, face_count, "
    "face_vertex_count, crease_count, corner_count, hole_count, min_x, min_y, min_z, max_x, "
    "max_y, max_z, sha256, create_time_us, stored_bytes";
inline constexpr int kMetadataColumnCount = 20;

}  // namespace tessera::server::schema
