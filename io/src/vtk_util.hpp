/* vtk_util.hpp - what io/src's VTK writer and reader share (private): VTK's messages, kept
 * for ours and never printed, and the mesh formats' file names. */
#pragma once

#include "tp_io.h"

#include <string>
#include <vector>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

namespace tpvtk {

/* The first VTK error of the current call on this thread (vtk_util.cpp). */
extern thread_local std::string t_vtk_error;

/* Replaces VTK's output window for the whole process (it would print to stderr, in colour,
 * through its logger as well) by one that keeps the text for our messages. */
void quiet_vtk();

/* Clears the kept error at the start of a call. */
struct VtkErrors {
    VtkErrors()
    {
        quiet_vtk();
        t_vtk_error.clear();
    }
    bool any() const
    {
        return !t_vtk_error.empty();
    }
    const char* text() const
    {
        return t_vtk_error.empty() ? "unknown error" : t_vtk_error.c_str();
    }
};

/* The lower-case extension of path (".vtp"), or "" without one. */
std::string lower_ext(const std::string& path);

/* The mesh format of a file name's extension (tp_output_format_for, TP_OUTPUT_MESH);
 * TP_MESH_DEFAULT for none of ours. */
tp_mesh_format format_of(const std::string& path);

/* The triangles tris (all when NULL) and the points they use (all points when NULL: then
 * points is ignored, else points lists the mesh points in their new order and local holds the
 * triangles' corners as indices into it), with m's point, cell and field data; the field data's
 * triangle_count is field_triangle_count, or the triangles' own count when 0
 * (vtk_mesh_write.cpp). */
vtkSmartPointer<vtkPolyData> build_polydata(const tp_mesh* m, const std::vector<size_t>* tris,
                                            const std::vector<size_t>* points,
                                            const std::vector<size_t>* local,
                                            size_t field_triangle_count);

} // namespace tpvtk
