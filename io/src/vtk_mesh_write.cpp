/* vtk_mesh_write.cpp - triangle meshes for ParaView through VTK's own writers: .vtp (XML
 * PolyData, binary, zlib), .vtk (legacy, binary), .vtm (XML multiblock, one PolyData block per
 * patch). tp_mesh_check_size and tp_mesh_write.
 *
 * Writing. VTK builds every file in memory (WriteToOutputString) and we write the bytes:
 *  - VTK 9.1's XML writers free uninitialised pointers when the disk fills in the middle of a
 *    write (vtkXMLUnstructuredDataWriter::WriteAPiece calls DeletePositionArrays, which only
 *    appended mode ever allocated): a full disk would crash the program, not fail the write;
 *  - the writers report a failure as a vtkErrorCode at best (the XML writers' Write() returns
 *    1 even when the file could not be opened), and a full disk or a quota may only show at
 *    fsync() or close(), which VTK does not check; our own write(), fsync() and close() say
 *    what went wrong (strerror).
 * A .vtp or .vtk goes through tp_file_write (atomic_write.cpp): a new temporary file of an
 * unpredictable name beside its final one, renamed into place only when complete.
 *
 * A .vtm is an index plus a folder of pieces: x.vtm names x/x_0.vtp, x/x_1.vtp, ... (VTK's
 * vtkXMLMultiBlockDataWriter uses the same layout; we write the pieces with vtkXMLPolyDataWriter
 * for the reason above, and the few lines of index ourselves). Both are built inside one
 * temporary folder beside x.vtm; then the folder of pieces is renamed into place (an older one
 * of the same name is moved aside first, and only if it holds nothing but pieces), then the
 * index. Any failure undoes the renames and removes the temporary folder; so does SIGINT or
 * SIGTERM (checked between pieces and between each piece's chunks), the folder holding off
 * the signal's default action while it lives.
 */
#include "atomic_write.hpp"
#include "io_util.hpp"
#include "tp_io.h"
#include "vtk_util.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <filesystem>
#include <memory>
#include <new>
#include <string>
#include <sys/stat.h>
#include <type_traits>
#include <unistd.h>
#include <vector>

using namespace tpvtk;
using tpio::fail;
namespace fs = std::filesystem;

/* ---------------------------------------------------------------------------------------------
 * tp_mesh -> vtkPolyData
 */
static void add_string(vtkFieldData* fd, const char* name, const char* value)
{
    if (!value || !*value) /* NULL or "": not known, no array */
        return;
    vtkNew<vtkStringArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
}

/* Field data shared by the whole file (each .vtm block gets its own triangle_count). */
static void add_field_data(vtkFieldData* fd, const tp_mesh* m, size_t triangle_count)
{
    add_string(fd, "crs_wkt", m->crs_wkt);
    vtkNew<vtkIntArray> epsg;
    epsg->SetName("epsg");
    epsg->InsertNextValue(m->epsg);
    fd->AddArray(epsg);
    add_string(fd, "utm_zone", m->utm_zone);
    add_string(fd, "source_file", m->source_file);
    add_string(fd, "camera", m->camera);
    add_string(fd, "lod_params", m->lod_params);
    add_string(fd, "program_version", m->program_version);
    add_string(fd, "void_filled_note", m->void_filled_note);
    vtkNew<vtkDoubleArray> origin;
    origin->SetName("origin");
    origin->SetNumberOfComponents(3);
    origin->InsertNextTuple(m->origin);
    fd->AddArray(origin);
    vtkNew<vtkIdTypeArray> count;
    count->SetName("triangle_count");
    count->InsertNextValue((vtkIdType)triangle_count);
    fd->AddArray(count);
}

/* See vtk_util.hpp. */
vtkSmartPointer<vtkPolyData> tpvtk::build_polydata(const tp_mesh* m,
                                                   const std::vector<size_t>* tris,
                                                   const std::vector<size_t>* points,
                                                   const std::vector<size_t>* local,
                                                   size_t field_triangle_count)
{
    const vtkIdType np = points ? (vtkIdType)points->size() : (vtkIdType)m->point_count;
    const vtkIdType nt = tris ? (vtkIdType)tris->size() : (vtkIdType)m->triangle_count;
    auto pt = [&](vtkIdType i) -> size_t { return points ? (*points)[(size_t)i] : (size_t)i; };
    auto tri = [&](vtkIdType i) -> size_t { return tris ? (*tris)[(size_t)i] : (size_t)i; };

    auto pd = vtkSmartPointer<vtkPolyData>::New();

    vtkNew<vtkDoubleArray> xyz;
    xyz->SetNumberOfComponents(3);
    xyz->SetNumberOfTuples(np);
    double* x = xyz->GetPointer(0);
    for (vtkIdType i = 0; i < np; ++i)
        std::memcpy(x + 3 * i, m->xyz + 3 * pt(i), 3 * sizeof(double));
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetData(xyz);
    pd->SetPoints(pts);

    /* 32-bit offsets and connectivity when they fit (half the memory, and the XML writer writes
     * them as Int32: smaller files), else 64-bit */
    auto corner = [&](vtkIdType i, int k) -> vtkIdType {
        return local ? (vtkIdType)(*local)[(size_t)(3 * i + k)]
                     : (vtkIdType)m->triangles[3 * tri(i) + k];
    };
    vtkNew<vtkCellArray> cells;
    auto fill = [&](auto* offsets, auto* conn) {
        offsets->SetNumberOfValues(nt + 1);
        conn->SetNumberOfValues(3 * nt);
        auto* o = offsets->GetPointer(0);
        auto* c = conn->GetPointer(0);
        using T = std::remove_pointer_t<decltype(o)>;
        for (vtkIdType i = 0; i <= nt; ++i)
            o[i] = (T)(3 * i);
        for (vtkIdType i = 0; i < nt; ++i)
            for (int k = 0; k < 3; ++k)
                c[3 * i + k] = (T)corner(i, k);
        cells->SetData(offsets, conn);
    };
    if (np < INT32_MAX && 3 * nt < INT32_MAX) {
        vtkNew<vtkTypeInt32Array> offsets, conn;
        fill(offsets.Get(), conn.Get());
    } else {
        vtkNew<vtkTypeInt64Array> offsets, conn;
        fill(offsets.Get(), conn.Get());
    }
    pd->SetPolys(cells);

    if (m->elevation_m) {
        vtkNew<vtkDoubleArray> a;
        a->SetName("elevation_m");
        a->SetNumberOfValues(np);
        for (vtkIdType i = 0; i < np; ++i)
            a->SetValue(i, m->elevation_m[pt(i)]);
        pd->GetPointData()->SetScalars(a); /* ParaView colours by it at first */
    }
    if (m->void_filled) {
        vtkNew<vtkUnsignedCharArray> a;
        a->SetName("void_filled");
        a->SetNumberOfValues(np);
        for (vtkIdType i = 0; i < np; ++i)
            a->SetValue(i, m->void_filled[pt(i)]);
        pd->GetPointData()->AddArray(a);
    }
    if (m->patch_id) {
        vtkNew<vtkIntArray> a;
        a->SetName("patch_id");
        a->SetNumberOfValues(nt);
        for (vtkIdType i = 0; i < nt; ++i)
            a->SetValue(i, m->patch_id[tri(i)]);
        pd->GetCellData()->AddArray(a);
    }
    if (m->lod) {
        vtkNew<vtkUnsignedCharArray> a;
        a->SetName("lod");
        a->SetNumberOfValues(nt);
        for (vtkIdType i = 0; i < nt; ++i)
            a->SetValue(i, m->lod[tri(i)]);
        pd->GetCellData()->AddArray(a);
    }
    if (m->max_error_m) {
        vtkNew<vtkDoubleArray> a;
        a->SetName("max_error_m");
        a->SetNumberOfValues(nt);
        for (vtkIdType i = 0; i < nt; ++i)
            a->SetValue(i, m->max_error_m[tri(i)]);
        pd->GetCellData()->AddArray(a);
    }
    add_field_data(pd->GetFieldData(), m, field_triangle_count ? field_triangle_count : (size_t)nt);
    return pd;
}

namespace {

std::string base_of(const std::string& path)
{
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

/* Holds interruption (a signal only sets the flag) while the temporary folder lives, and
 * removes it whatever happens to our caller. */
struct TempGuard {
    std::string name;
    TempGuard()
    {
        tp_interrupt_hold();
    }
    ~TempGuard()
    {
        if (!name.empty()) {
            std::error_code ec;
            fs::remove_all(name, ec);
        }
        tp_interrupt_release();
    }
    TempGuard(const TempGuard&) = delete;
    TempGuard& operator=(const TempGuard&) = delete;
};

/* The bytes of a .vtp; false with VTK's reason in *why. */
bool vtp_bytes(vtkPolyData* pd, std::string* out, std::string* why)
{
    VtkErrors errors;
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetInputData(pd);
    w->WriteToOutputStringOn();
    w->SetDataModeToBinary();
    w->SetCompressorTypeToZLib();
    w->SetHeaderTypeToUInt64(); /* no 4 GiB limit on an array */
    /* 32-bit connectivity and offsets when they fit: a third smaller files */
    if (pd->GetNumberOfPoints() < INT32_MAX && 3 * pd->GetNumberOfCells() < INT32_MAX)
        w->SetIdTypeToInt32();
    if (!w->Write() || w->GetErrorCode() != vtkErrorCode::NoError || errors.any()) {
        *why =
            errors.any() ? errors.text() : vtkErrorCode::GetStringFromErrorCode(w->GetErrorCode());
        return false;
    }
    *out = w->GetOutputString();
    return true;
}

/* The bytes of a legacy .vtk (owned by *out, new[]'d by VTK). */
bool vtk_bytes(vtkPolyData* pd, std::unique_ptr<char[]>* out, size_t* size, std::string* why)
{
    VtkErrors errors;
    vtkNew<vtkPolyDataWriter> w;
    w->SetInputData(pd);
    w->WriteToOutputStringOn();
    w->SetFileTypeToBinary();
    w->SetHeader("terrapatch triangle mesh");
    /* Version 4.2 (32-bit cell arrays) is what older readers (VTK < 9, meshio, VisIt) know;
     * 5.1 only when the connectivity would not fit. */
    if (pd->GetNumberOfPoints() < INT32_MAX && 4 * pd->GetNumberOfCells() < INT32_MAX)
        w->SetFileVersion(vtkDataWriter::VTK_LEGACY_READER_VERSION_4_2);
    if (!w->Write() || w->GetErrorCode() != vtkErrorCode::NoError || errors.any()) {
        *why =
            errors.any() ? errors.text() : vtkErrorCode::GetStringFromErrorCode(w->GetErrorCode());
        return false;
    }
    *size = (size_t)w->GetOutputStringLength();
    out->reset(w->RegisterAndGetOutputString());
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * Writers
 */
tp_status write_single(const std::string& path, tp_mesh_format format, const tp_mesh* m,
                       tp_error* err)
{
    vtkSmartPointer<vtkPolyData> pd = build_polydata(m, nullptr, nullptr, nullptr, 0);
    std::string why, xml;
    std::unique_ptr<char[]> legacy;
    const char* data;
    size_t size = 0;
    if (format == TP_MESH_VTP) {
        if (!vtp_bytes(pd, &xml, &why))
            return fail(err, TP_ERR_BACKEND, "%s: VTK could not write the mesh: %s", path.c_str(),
                        why.c_str());
        data = xml.data();
        size = xml.size();
    } else {
        if (!vtk_bytes(pd, &legacy, &size, &why))
            return fail(err, TP_ERR_BACKEND, "%s: VTK could not write the mesh: %s", path.c_str(),
                        why.c_str());
        data = legacy.get();
    }
    pd = nullptr; /* the mesh copy is not needed any more */
    if (!data || size == 0)
        return fail(err, TP_ERR_BACKEND, "%s: VTK wrote an empty file", path.c_str());

    return tp_file_write(path.c_str(), data, size, err);
}

/* Escapes text for an XML attribute value. */
std::string xml_attr(const std::string& s)
{
    std::string r;
    for (char c : s) {
        switch (c) {
        case '&': r += "&amp;"; break;
        case '<': r += "&lt;"; break;
        case '>': r += "&gt;"; break;
        case '"': r += "&quot;"; break;
        default: r += c;
        }
    }
    return r;
}

/* True if dir holds nothing but pieces of a .vtm named prefix ("<prefix>_<digits, _>.vtp",
 * VTK's names), so replacing it loses nothing of anyone else's. */
bool only_pieces(const std::string& dir, const std::string& prefix)
{
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::string n = it->path().filename().string();
        if (!it->is_regular_file(ec) || n.size() <= prefix.size() + 5 ||
            n.compare(0, prefix.size() + 1, prefix + "_") != 0 ||
            n.compare(n.size() - 4, 4, ".vtp") != 0)
            return false;
        for (size_t i = prefix.size() + 1; i < n.size() - 4; ++i)
            if (!std::isdigit((unsigned char)n[i]) && n[i] != '_')
                return false;
    }
    return !ec;
}

tp_status write_vtm(const std::string& path, const tp_mesh* m, tp_error* err)
{
    const std::string dir = tpio::dir_of(path), name = base_of(path);
    const size_t dot = name.find_last_of('.');
    if (dot == std::string::npos || dot == 0)
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: a multiblock mesh needs a name with an extension (its pieces go in a "
                    "folder named after the name without it)",
                    path.c_str());
    const std::string prefix = name.substr(0, dot);
    const std::string pieces = dir + "/" + prefix; /* the folder of pieces, final name */

    /* Triangles by patch, in increasing patch id; one block ("patch_0") without patch ids. */
    std::vector<size_t> order(m->triangle_count);
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    if (m->patch_id)
        std::stable_sort(order.begin(), order.end(),
                         [m](size_t a, size_t b) { return m->patch_id[a] < m->patch_id[b]; });

    struct stat st;
    bool replace_old = false;
    if (lstat(pieces.c_str(), &st) == 0) {
        if (!S_ISDIR(st.st_mode) || !only_pieces(pieces, prefix))
            return fail(err, TP_ERR_IO,
                        "%s: cannot write: %s exists and is not a folder of mesh pieces "
                        "(%s_N.vtp); not replacing it",
                        path.c_str(), pieces.c_str(), prefix.c_str());
        replace_old = true;
    }

    TempGuard guard;
    int e = tpio::make_temp_dir(path, &guard.name);
    if (e)
        return tpio::write_failed(err, path, e);
    const std::string tmp = guard.name;
    if (mkdir((tmp + "/" + prefix).c_str(), 0777) != 0)
        return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(errno));

    std::string index = "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" "
                        "version=\"1.0\" byte_order=\"";
    const uint16_t one = 1;
    index += *(const uint8_t*)&one ? "LittleEndian" : "BigEndian";
    index += "\">\n  <vtkMultiBlockDataSet>\n";

    std::vector<int64_t> local_of(m->point_count, -1);
    std::vector<size_t> tris, points, local;
    size_t block = 0;
    for (size_t begin = 0; begin < order.size();) {
        size_t end = begin;
        const int32_t id = m->patch_id ? m->patch_id[order[begin]] : 0;
        while (end < order.size() && (!m->patch_id || m->patch_id[order[end]] == id))
            ++end;
        tris.assign(order.begin() + (ptrdiff_t)begin, order.begin() + (ptrdiff_t)end);
        points.clear();
        local.clear();
        for (size_t t : tris)
            for (int k = 0; k < 3; ++k) {
                const size_t p = (size_t)m->triangles[3 * t + k];
                if (local_of[p] < 0) {
                    local_of[p] = (int64_t)points.size();
                    points.push_back(p);
                }
                local.push_back((size_t)local_of[p]);
            }
        for (size_t p : points)
            local_of[p] = -1;

        if (tp_interrupted())
            return tpio::write_failed(err, path, EINTR);
        vtkSmartPointer<vtkPolyData> pd = build_polydata(m, &tris, &points, &local, 0);
        std::string bytes, why;
        if (!vtp_bytes(pd, &bytes, &why))
            return fail(err, TP_ERR_BACKEND, "%s: VTK could not write the mesh: %s", path.c_str(),
                        why.c_str());
        const std::string file = prefix + "/" + prefix + "_" + std::to_string(block) + ".vtp";
        e = tpio::write_new_file(tmp + "/" + file, bytes.data(), bytes.size());
        if (e)
            return tpio::write_failed(err, path, e);
        index += "    <DataSet index=\"" + std::to_string(block) + "\" name=\"patch_" +
                 std::to_string(id) + "\" file=\"" + xml_attr(file) + "\"/>\n";
        ++block;
        begin = end;
    }
    index += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    e = tpio::write_new_file(tmp + "/" + name, index.data(), index.size());
    if (e)
        return tpio::write_failed(err, path, e);
    const bool have_pieces = block > 0; /* no triangles: an index of no blocks, no folder */
    if (have_pieces)
        tpio::sync_dir(tmp + "/" + prefix);
    if (tp_interrupted()) /* the last moment to stop with nothing changed */
        return tpio::write_failed(err, path, EINTR);

    /* Into place: the old pieces aside, the new pieces, then the index (which replaces any
     * older index atomically). Each failure undoes what was done; the guard removes tmp. */
    const std::string old = tmp + "/old";
    if (replace_old && std::rename(pieces.c_str(), old.c_str()) != 0)
        return fail(err, TP_ERR_IO, "%s: cannot write: moving %s aside: %s", path.c_str(),
                    pieces.c_str(), std::strerror(errno));
    if (have_pieces && std::rename((tmp + "/" + prefix).c_str(), pieces.c_str()) != 0) {
        e = errno;
        if (replace_old)
            (void)std::rename(old.c_str(), pieces.c_str());
        return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
    }
    if (std::rename((tmp + "/" + name).c_str(), path.c_str()) != 0) {
        e = errno;
        if (have_pieces)
            (void)std::rename(pieces.c_str(), (tmp + "/" + prefix).c_str());
        if (replace_old)
            (void)std::rename(old.c_str(), pieces.c_str());
        return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
    }
    tpio::sync_dir(dir);
    return TP_OK; /* the guard removes tmp with the old pieces in it */
}

} // namespace

/* ---------------------------------------------------------------------------------------------
 * C interface
 */
extern "C" tp_status tp_mesh_check_size(tp_mesh_format format, size_t point_count,
                                        size_t triangle_count, tp_error* err)
{
    if (format != TP_MESH_DEFAULT && format != TP_MESH_VTP && format != TP_MESH_VTK &&
        format != TP_MESH_VTM)
        return fail(err, TP_ERR_INVALID_ARG, "mesh: unknown mesh format %d", (int)format);
    try { /* integer comparisons and a message: nothing should throw */
        /* Every format numbers points, and the connectivity (3 ids per triangle, offsets up to
         * 3 * triangles), in vtkIdType. */
        const char* name = format == TP_MESH_VTP   ? "a .vtp file"
                           : format == TP_MESH_VTK ? "a legacy .vtk file"
                           : format == TP_MESH_VTM ? "a .vtm file"
                                                   : "a mesh file";
        const unsigned long long id_max = (unsigned long long)VTK_ID_MAX;
        const int id_bits = (int)(8 * sizeof(vtkIdType));
        if ((unsigned long long)point_count > id_max)
            return fail(err, TP_ERR_INVALID_ARG,
                        "%zu points: %s holds at most %llu (VTK's %d-bit vtkIdType)", point_count,
                        name, id_max, id_bits);
        if ((unsigned long long)triangle_count > (id_max - 1) / 3)
            return fail(err, TP_ERR_INVALID_ARG,
                        "%zu triangles: %s holds at most %llu (3 point ids each, in VTK's %d-bit "
                        "vtkIdType, up to %llu)",
                        triangle_count, name, (id_max - 1) / 3, id_bits, id_max);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "mesh");
    }
}

extern "C" tp_status tp_mesh_write(const char* path, tp_mesh_format format, const tp_mesh* mesh,
                                   tp_error* err)
{
    if (!path || !*path || !mesh)
        return fail(err, TP_ERR_INVALID_ARG, "mesh: bad arguments (path or mesh is NULL)");
    if ((mesh->point_count && !mesh->xyz) || (mesh->triangle_count && !mesh->triangles))
        return fail(err, TP_ERR_INVALID_ARG, "%s: mesh without %s", path,
                    mesh->point_count && !mesh->xyz ? "xyz" : "triangles");
    try {
        const std::string p = path;
        if (p.back() == '/')
            return fail(err, TP_ERR_INVALID_ARG, "%s: a file name is needed, not a folder", path);
        if (format == TP_MESH_DEFAULT) {
            format = format_of(p);
            if (format == TP_MESH_DEFAULT)
                return fail(err, TP_ERR_INVALID_ARG,
                            "%s: unknown mesh extension '%s': expected .vtp, .vtk or .vtm", path,
                            lower_ext(p).empty() ? "(none)" : lower_ext(p).c_str());
        } else if (format != TP_MESH_VTP && format != TP_MESH_VTK && format != TP_MESH_VTM) {
            return fail(err, TP_ERR_INVALID_ARG, "%s: unknown mesh format %d", path, (int)format);
        }
        tp_error size_err;
        if (tp_mesh_check_size(format, mesh->point_count, mesh->triangle_count, &size_err) != TP_OK)
            return fail(err, TP_ERR_INVALID_ARG, "%s: %s", path, size_err.message);
        for (size_t i = 0; i < 3 * mesh->triangle_count; ++i)
            if (mesh->triangles[i] >= mesh->point_count)
                return fail(err, TP_ERR_INVALID_ARG,
                            "%s: triangle %zu: expected point indices below %zu, got %llu", path,
                            i / 3, mesh->point_count, (unsigned long long)mesh->triangles[i]);
        quiet_vtk();
        return format == TP_MESH_VTM ? write_vtm(p, mesh, err) : write_single(p, format, mesh, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}
