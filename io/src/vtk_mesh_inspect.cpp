/* vtk_mesh_inspect.cpp - tp_mesh_inspect: a .vtp, .vtk or .vtm read back with VTK's own
 * readers and summarised (counts, ranges, field data, boundary and non-manifold edges).
 *
 * Reading. Boundary edges are used by one polygon, non-manifold edges by three or more (as
 * vtkFeatureEdges defines them; it is not used, see edge_counts); loops are the connected
 * components of the boundary edges. The blocks of a .vtm share the points on patch seams, so
 * they are appended and their coincident points merged (vtkCleanPolyData, tolerance 0: exact
 * positions) before the edges are counted; so are the pieces of a .vtp written in pieces
 * (tp_mesh_write_pieces), which repeat the points where they meet.
 */
#include "io_util.hpp"
#include "tp_io.h"
#include "vtk_util.hpp"

#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCleanPolyData.h>
#include <vtkDataObjectTree.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

using namespace tpvtk;
using tpio::fail;

namespace {

/* ---------------------------------------------------------------------------------------------
 * Reading back
 */
struct Loaded {
    std::vector<vtkSmartPointer<vtkPolyData>> blocks;
    vtkSmartPointer<vtkFieldData> composite_fields; /* .vtm only; may be empty */
    int pieces = 1; /* a .vtp's pieces (tp_mesh_write_pieces), read as one PolyData */
};

tp_status load(const char* path, tp_mesh_format format, Loaded* out, tp_error* err)
{
    VtkErrors errors;
    if (format == TP_MESH_VTM) {
        vtkNew<vtkXMLMultiBlockDataReader> r;
        r->SetFileName(path);
        r->Update();
        vtkDataObjectTree* tree = vtkDataObjectTree::SafeDownCast(r->GetOutputDataObject(0));
        if (errors.any() || !tree)
            return fail(err, TP_ERR_BAD_DATA, "%s: not a readable VTK multiblock file: %s", path,
                        errors.text());
        out->composite_fields = tree->GetFieldData();
        vtkSmartPointer<vtkDataObjectTreeIterator> it;
        it.TakeReference(tree->NewTreeIterator());
        it->VisitOnlyLeavesOn();
        it->TraverseSubTreeOn();
        it->SkipEmptyNodesOn();
        size_t n = 0;
        for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem(), ++n) {
            vtkDataObject* d = it->GetCurrentDataObject();
            vtkPolyData* pd = vtkPolyData::SafeDownCast(d);
            if (!pd)
                return fail(err, TP_ERR_BAD_DATA, "%s: block %zu is a %s, not PolyData", path, n,
                            d->GetClassName());
            out->blocks.push_back(pd);
        }
        return TP_OK;
    }
    vtkSmartPointer<vtkPolyData> pd;
    if (format == TP_MESH_VTP) {
        vtkNew<vtkXMLPolyDataReader> r;
        r->SetFileName(path);
        r->Update();
        pd = r->GetOutput();
        out->pieces = r->GetNumberOfPieces();
        if (errors.any() || r->GetErrorCode() != vtkErrorCode::NoError || !pd)
            return fail(err, TP_ERR_BAD_DATA, "%s: not a readable VTK XML PolyData file: %s", path,
                        errors.any() ? errors.text()
                                     : vtkErrorCode::GetStringFromErrorCode(r->GetErrorCode()));
    } else {
        vtkNew<vtkPolyDataReader> r;
        r->SetFileName(path);
        r->Update();
        pd = r->GetOutput();
        if (errors.any() || r->GetErrorCode() != vtkErrorCode::NoError || !pd)
            return fail(err, TP_ERR_BAD_DATA, "%s: not a readable legacy VTK PolyData file: %s",
                        path,
                        errors.any() ? errors.text()
                                     : vtkErrorCode::GetStringFromErrorCode(r->GetErrorCode()));
    }
    out->blocks.push_back(pd);
    return TP_OK;
}

/* Boundary edges (used by one polygon), their loops, and non-manifold edges (used by three or
 * more) of the polygons of pd, by point id. vtkFeatureEdges defines them the same way, but
 * VTK 9.1's allocates (points / 20) * (points / 10) ids for its output lines: 40 GB for a
 * mesh of a million points. So the edges are counted here: sorted (min, max) point pairs. */
tp_status edge_counts(const char* path, vtkPolyData* pd, tp_mesh_summary* s, tp_error* err)
{
    s->boundary_edges = s->boundary_loops = s->non_manifold_edges = 0;
    if (!pd)
        return TP_OK;
    const vtkIdType np = pd->GetNumberOfPoints();
    if ((uint64_t)np > UINT32_MAX)
        return fail(err, TP_ERR_BAD_DATA, "%s: %lld points: too many to count edges", path,
                    (long long)np);
    vtkCellArray* polys = pd->GetPolys();
    std::vector<uint64_t> edges;
    edges.reserve((size_t)polys->GetNumberOfConnectivityIds());
    vtkIdType n;
    const vtkIdType* ids;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
        for (vtkIdType k = 0; k < n; ++k) {
            uint64_t a = (uint64_t)ids[k], b = (uint64_t)ids[(k + 1) % n];
            if (a == b || a >= (uint64_t)np || b >= (uint64_t)np)
                continue; /* a degenerate corner, or a file that points nowhere */
            edges.push_back(a < b ? a << 32 | b : b << 32 | a);
        }
    std::sort(edges.begin(), edges.end());

    /* Loops: connected components of the boundary edges (union-find over their points). */
    std::vector<uint32_t> parent;
    auto find = [&parent](uint32_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<uint32_t> ends; /* points on a boundary edge */
    for (size_t i = 0, j; i < edges.size(); i = j) {
        for (j = i + 1; j < edges.size() && edges[j] == edges[i];)
            ++j;
        if (j - i >= 3)
            s->non_manifold_edges++;
        if (j - i != 1)
            continue;
        s->boundary_edges++;
        if (parent.empty()) {
            parent.resize((size_t)np);
            for (size_t p = 0; p < parent.size(); ++p)
                parent[p] = (uint32_t)p;
        }
        uint32_t a = (uint32_t)(edges[i] >> 32), b = (uint32_t)edges[i];
        parent[find(a)] = find(b);
        ends.push_back(a);
        ends.push_back(b);
    }
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    for (uint32_t p : ends)
        s->boundary_loops += find(p) == p;
    return TP_OK;
}

/* A string array of one non-empty value. */
bool has_string(vtkFieldData* fd, const char* name)
{
    vtkStringArray* a = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
    return a && a->GetNumberOfValues() > 0 && !a->GetValue(0).empty();
}

tp_status summarise(const char* path, const Loaded& in, tp_mesh_format format, tp_mesh_summary* s,
                    tp_error* err)
{
    VtkErrors errors;
    *s = tp_mesh_summary{};
    s->blocks = in.blocks.size();
    s->pieces = (size_t)in.pieces;
    s->max_error_m = NAN;
    for (double& b : s->bounds)
        b = NAN;
    const int all = in.blocks.empty() ? 0 : 1;
    s->points_are_double = s->has_elevation = s->has_void_filled = all;
    s->has_patch_id = s->has_lod = s->has_max_error = all;

    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (vtkPolyData* pd : in.blocks) {
        const vtkIdType np = pd->GetNumberOfPoints();
        s->points += (size_t)np;
        vtkPoints* pts = pd->GetPoints();
        if (np > 0 && (!pts || pts->GetDataType() != VTK_DOUBLE))
            s->points_are_double = 0;
        for (vtkIdType i = 0; i < np; ++i) {
            double p[3];
            pts->GetPoint(i, p);
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], p[k]);
                hi[k] = std::max(hi[k], p[k]);
            }
        }
        vtkCellArray* polys = pd->GetPolys();
        const vtkIdType npolys = polys->GetNumberOfCells();
        size_t tri = 0;
        vtkNew<vtkIdList> ids;
        for (vtkIdType c = 0; c < npolys; ++c) {
            if (polys->GetCellSize(c) != 3)
                continue;
            tri++;
            polys->GetCellAtId(c, ids);
            double a[3], b[3], q[3];
            pts->GetPoint(ids->GetId(0), a);
            pts->GetPoint(ids->GetId(1), b);
            pts->GetPoint(ids->GetId(2), q);
            /* the normal's vertical part, (b - a) x (q - a) in (E, N) */
            double nz = (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
            s->downward_triangles += !(nz > 0);
        }
        s->triangles += tri;
        s->other_cells += (size_t)(pd->GetNumberOfCells() - (vtkIdType)tri);

        vtkPointData* ptd = pd->GetPointData();
        vtkCellData* cd = pd->GetCellData();
        s->has_elevation &= ptd->GetAbstractArray("elevation_m") != nullptr;
        s->has_void_filled &= ptd->GetAbstractArray("void_filled") != nullptr;
        if (vtkDataArray* vf = ptd->GetArray("void_filled"))
            for (vtkIdType i = 0; i < vf->GetNumberOfTuples(); ++i)
                s->void_filled_points += vf->GetComponent(i, 0) != 0;
        s->has_patch_id &= cd->GetAbstractArray("patch_id") != nullptr;
        s->has_lod &= cd->GetAbstractArray("lod") != nullptr;
        vtkDataArray* e = cd->GetArray("max_error_m");
        s->has_max_error &= e != nullptr;
        if (e)
            for (vtkIdType i = 0; i < e->GetNumberOfTuples(); ++i) {
                double v = e->GetComponent(i, 0);
                if (!std::isnan(v) && (std::isnan(s->max_error_m) || v > s->max_error_m))
                    s->max_error_m = v;
            }
    }
    if (s->points > 0)
        for (int k = 0; k < 3; ++k) {
            s->bounds[2 * k] = lo[k];
            s->bounds[2 * k + 1] = hi[k];
        }

    /* Field data: the composite's own, else the first block's. */
    vtkFieldData* fd = nullptr;
    if (in.composite_fields && in.composite_fields->GetNumberOfArrays() > 0)
        fd = in.composite_fields;
    else if (!in.blocks.empty())
        fd = in.blocks[0]->GetFieldData();
    s->has_crs = has_string(fd, "crs_wkt");
    s->has_source = has_string(fd, "source_file");
    s->has_version = has_string(fd, "program_version");

    tp_status st = TP_OK;
    if (format != TP_MESH_VTM && in.pieces <= 1) {
        st = edge_counts(path, in.blocks.empty() ? nullptr : in.blocks[0].Get(), s, err);
    } else if (!in.blocks.empty()) { /* a .vtm's blocks, a .vtp's pieces */
        vtkNew<vtkAppendPolyData> append;
        for (vtkPolyData* pd : in.blocks)
            append->AddInputData(pd);
        vtkNew<vtkCleanPolyData> clean;
        clean->SetInputConnection(append->GetOutputPort());
        clean->PointMergingOn();
        clean->SetTolerance(0.0); /* exact: vtkMergePoints */
        clean->Update();
        vtkPolyData* merged = clean->GetOutput();
        if (format != TP_MESH_VTM) { /* a .vtp's pieces: the points of the one surface */
            s->points = (size_t)merged->GetNumberOfPoints();
            s->void_filled_points = 0;
            if (vtkDataArray* vf = merged->GetPointData()->GetArray("void_filled"))
                for (vtkIdType i = 0; i < vf->GetNumberOfTuples(); ++i)
                    s->void_filled_points += vf->GetComponent(i, 0) != 0;
        }
        st = edge_counts(path, merged, s, err);
    }
    if (st != TP_OK)
        return st;
    if (errors.any())
        return fail(err, TP_ERR_BACKEND, "%s: VTK could not analyse the mesh: %s", path,
                    errors.text());
    return TP_OK;
}

} // namespace

/* ---------------------------------------------------------------------------------------------
 * C interface
 */
extern "C" tp_status tp_mesh_inspect(const char* path, tp_mesh_summary* out, tp_error* err)
{
    if (!path || !*path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "mesh: bad arguments (path or out is NULL)");
    try {
        tp_mesh_format format = format_of(path);
        if (format == TP_MESH_DEFAULT)
            return fail(err, TP_ERR_INVALID_ARG,
                        "%s: unknown mesh extension '%s': expected .vtp, .vtk or .vtm", path,
                        lower_ext(path).empty() ? "(none)" : lower_ext(path).c_str());
        /* Our own reason first: VTK's readers only say they could not open it. */
        struct stat st;
        if (stat(path, &st) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
        if (S_ISDIR(st.st_mode))
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(EISDIR));
        if (access(path, R_OK) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
        if (st.st_size == 0)
            return fail(err, TP_ERR_BAD_DATA, "%s: empty file", path);
        Loaded loaded;
        tp_status s = load(path, format, &loaded, err);
        if (s != TP_OK)
            return s;
        tp_mesh_summary summary;
        s = summarise(path, loaded, format, &summary, err);
        if (s == TP_OK)
            *out = summary;
        return s;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_mesh_read_points(const char* path, double** xyz, size_t* count,
                                         tp_error* err)
{
    if (!path || !*path || !xyz || !count)
        return fail(err, TP_ERR_INVALID_ARG, "mesh: bad arguments (path, xyz or count is NULL)");
    try {
        tp_mesh_format format = format_of(path);
        if (format != TP_MESH_VTP && format != TP_MESH_VTK)
            return fail(err, TP_ERR_INVALID_ARG, "%s: expected a .vtp or .vtk file", path);
        struct stat st;
        if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
        Loaded loaded;
        tp_status s = load(path, format, &loaded, err);
        if (s != TP_OK)
            return s;
        vtkPoints* pts = loaded.blocks[0]->GetPoints();
        size_t n = pts ? (size_t)pts->GetNumberOfPoints() : 0;
        double* out = (double*)std::malloc(3 * (n ? n : 1) * sizeof(double));
        if (!out)
            return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory reading the points", path);
        for (size_t i = 0; i < n; i++)
            pts->GetPoint((vtkIdType)i, out + 3 * i);
        *xyz = out;
        *count = n;
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
