/*
 * tp_io/mesh.h - triangle meshes for ParaView, written and read back through VTK.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_MESH_H
#define TP_IO_MESH_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Triangle meshes for ParaView (io/src/vtk_mesh_write.cpp and vtk_mesh_inspect.cpp, VTK's own writers and readers)
 */
typedef struct tp_mesh {
    size_t point_count;
    const double* xyz;          /* 3 per point: E, N (render CRS, or minus origin), elevation m */
    const double* elevation_m;  /* per point: point data "elevation_m" */
    const uint8_t* void_filled; /* per point: point data "void_filled" (0/1) */
    size_t triangle_count;
    const uint64_t* triangles;  /* 3 point indices per triangle, counter-clockwise from above */
    const int32_t* patch_id;    /* per triangle: cell data "patch_id" */
    const uint8_t* lod;         /* per triangle: cell data "lod" (k = n is full resolution) */
    const double* max_error_m;  /* per triangle: cell data "max_error_m" */
    /* Field data (strings may be NULL or ""): */
    const char* crs_wkt;
    int epsg;
    const char* utm_zone; /* e.g. "31n", "UPS n" (tp_zone_format, TP_ZONE_STYLE_SHORT) */
    const char* source_file;
    const char* camera;         /* the camera as a --camera-geo / --camera string */
    const char* lod_params;     /* e.g. "mode=error tau_px=1" */
    const char* program_version;
    double origin[3];           /* subtracted from every point (0 unless --origin local) */
    const char* void_filled_note; /* field data "void_filled_note" (NULL or "": none), e.g.
                                     why void_filled is not known (a store's export) */
} tp_mesh;

typedef enum tp_mesh_format {
    TP_MESH_DEFAULT = 0, /* from the extension: .vtp, .vtk or .vtm */
    TP_MESH_VTP,         /* VTK XML PolyData, binary, compressed */
    TP_MESH_VTK,         /* legacy VTK, binary */
    TP_MESH_VTM          /* VTK XML multiblock, one PolyData block per patch */
} tp_mesh_format;

/* Checks point_count and triangle_count against the limits of format (TP_MESH_DEFAULT: of every
 * format), without allocating: every format numbers points and the 3 point ids of each
 * triangle with VTK's vtkIdType, 64-bit in Debian's VTK 9.1, so a mesh may hold up to
 * 2^63 - 1 points and (2^63 - 2) / 3 triangles. (Legacy .vtk files are written as version 4.2,
 * 32-bit, when the mesh fits and as 5.1, 64-bit, when not; .vtm pieces are single patches.)
 * TP_ERR_INVALID_ARG with a message naming the count and the limit; TP_OK otherwise. */
tp_status tp_mesh_check_size(tp_mesh_format format, size_t point_count, size_t triangle_count,
                             tp_error* err);

/* Writes the mesh with VTK's writers: points as doubles, triangles as cells (not strips), the
 * point, cell and field data above (field data also holds "triangle_count"). Atomic: .vtp and
 * .vtk go through tp_file_write; a .vtm's index and pieces are built in a new temporary folder
 * of an unpredictable name beside path and renamed into place. On any failure (unwritable
 * directory, full disk, bad extension, counts beyond tp_mesh_check_size's limits, SIGINT or
 * SIGTERM after tp_interrupt_install: tp_interrupted() then says which) nothing is left behind,
 * older files stay as they were, and the message names the path. */
tp_status tp_mesh_write(const char* path, tp_mesh_format format, const tp_mesh* mesh,
                        tp_error* err);

/* Fills mesh (already holding the field data given to tp_mesh_write_pieces) with piece number
 * piece (0 .. piece_count - 1, asked for in order): its points and triangles, indices local to
 * the piece, and the same point and cell data arrays in every piece (non-NULL pointers, also
 * when a piece is empty). The arrays stay the caller's and must live until the next call or
 * the end of tp_mesh_write_pieces. Returns TP_OK, or a failure with err set: the write stops
 * and nothing is left behind. */
typedef tp_status (*tp_mesh_piece_fn)(void* user, size_t piece, tp_mesh* mesh, tp_error* err);

/* Writes a .vtp of piece_count pieces (VTK's XML PolyData pieces, appended raw data,
 * compressed), asking piece_fn for each in turn and writing it before asking for the next:
 * memory follows the largest piece, not the mesh, so a mesh of any size streams to disk. The
 * pieces are independent PolyData in one file, read by VTK and ParaView as one dataset; points
 * where pieces meet are repeated (ParaView's Clean filter merges them). fields gives the field
 * data (its arrays are ignored); "triangle_count" is triangle_total. Each piece holds fewer
 * than 2^31 points and triangles. Atomic as tp_mesh_write (a temporary file beside path,
 * renamed when complete; on a failure, a full disk or a signal nothing is left and an older
 * file stays). TP_ERR_INVALID_ARG for a path not ending in .vtp, a piece's index out of range
 * or a piece too large. */
tp_status tp_mesh_write_pieces(const char* path, const tp_mesh* fields, size_t triangle_total,
                               size_t piece_count, tp_mesh_piece_fn piece_fn, void* user,
                               tp_error* err);

/* What a mesh file holds, read back with VTK's readers (tests, --check). */
typedef struct tp_mesh_summary {
    size_t points, triangles, other_cells;
    int points_are_double;
    int has_elevation, has_void_filled, has_patch_id, has_lod, has_max_error;
    int has_crs, has_source, has_version; /* field data present */
    size_t boundary_loops;   /* connected loops of boundary edges (vtkFeatureEdges) */
    size_t boundary_edges, non_manifold_edges;
    double max_error_m;      /* largest cell max_error_m */
    double bounds[6];        /* xmin, xmax, ymin, ymax, zmin, zmax */
    size_t blocks;           /* .vtm: number of blocks; else 1 */
    size_t pieces;           /* .vtp: its pieces (tp_mesh_write_pieces; 1 for tp_mesh_write).
                                With several, the points where they meet are merged (as a .vtm's
                                blocks are) before the edges are counted, and points and
                                void_filled_points count the merged surface's points */
    size_t void_filled_points; /* points whose void_filled is not 0 */
    size_t downward_triangles; /* triangles not counter-clockwise seen from above (E, N) */
} tp_mesh_summary;

tp_status tp_mesh_inspect(const char* path, tp_mesh_summary* out, tp_error* err);

/* The points of a .vtp or .vtk mesh (3 doubles each, in file order), read back with VTK's
 * readers (tests comparing two meshes point for point). *xyz is allocated with malloc (the
 * caller frees it); *xyz and *count are written only on success. TP_ERR_INVALID_ARG for
 * another extension, TP_ERR_IO, TP_ERR_BAD_DATA as tp_mesh_inspect. */
tp_status tp_mesh_read_points(const char* path, double** xyz, size_t* count, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_MESH_H */
