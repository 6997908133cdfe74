/* vtk_mesh.cpp - triangle meshes for ParaView through VTK's own writers and readers: .vtp (XML
 * PolyData, binary, zlib), .vtk (legacy, binary), .vtm (XML multiblock, one PolyData block per
 * patch); and tp_mesh_inspect, the same files read back and summarised.
 *
 * Writing. VTK builds every file in memory (WriteToOutputString) and we write the bytes:
 *  - VTK 9.1's XML writers free uninitialised pointers when the disk fills in the middle of a
 *    write (vtkXMLUnstructuredDataWriter::WriteAPiece calls DeletePositionArrays, which only
 *    appended mode ever allocated): a full disk would crash the program, not fail the write;
 *  - the writers report a failure as a vtkErrorCode at best (the XML writers' Write() returns
 *    1 even when the file could not be opened), and a full disk or a quota may only show at
 *    fsync() or close(), which VTK does not check; our own write(), fsync() and close() say
 *    what went wrong (strerror).
 * Every file goes to a new temporary name beside its final one (O_EXCL, so nothing of anyone
 * else's is overwritten) and is renamed into place only when complete.
 *
 * A .vtm is an index plus a folder of pieces: x.vtm names x/x_0.vtp, x/x_1.vtp, ... (VTK's
 * vtkXMLMultiBlockDataWriter uses the same layout; we write the pieces with vtkXMLPolyDataWriter
 * for the reason above, and the few lines of index ourselves). Both are built inside one
 * temporary folder beside x.vtm; then the folder of pieces is renamed into place (an older one
 * of the same name is moved aside first, and only if it holds nothing but pieces), then the
 * index. Any failure undoes the renames and removes the temporary folder.
 *
 * Reading. Boundary edges are used by one polygon, non-manifold edges by three or more (as
 * vtkFeatureEdges defines them; it is not used, see edge_counts); loops are the connected
 * components of the boundary edges. The blocks of a .vtm share the points on patch seams, so
 * they are appended and their coincident points merged (vtkCleanPolyData, tolerance 0: exact
 * positions) before the edges are counted.
 */
#include "io_util.hpp"
#include "tp_io.h"

#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCleanPolyData.h>
#include <vtkDataObjectTree.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fcntl.h>
#include <filesystem>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

using tpio::fail;
namespace fs = std::filesystem;

/* ---------------------------------------------------------------------------------------------
 * VTK's messages: kept (the first error of the current call), never printed.
 */
namespace {

thread_local std::string t_vtk_error;

/* "ERROR: In <file>, line <n>\n<Class> (<address>): <text>\n\n" -> "<text>" */
std::string vtk_message_text(const char* raw)
{
    std::string s = raw ? raw : "";
    if (s.compare(0, 10, "ERROR: In ") == 0) {
        size_t nl = s.find('\n');
        s = nl == std::string::npos ? std::string() : s.substr(nl + 1);
    }
    size_t p = s.find("): ");
    if (p != std::string::npos && p < 128)
        s = s.substr(p + 3);
    size_t end = s.find("\n\n"); /* the executive appends a whole vtkInformation dump */
    if (end != std::string::npos)
        s.resize(end);
    while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
        s.pop_back();
    return s;
}

class CaptureOutputWindow : public vtkOutputWindow {
  public:
    static CaptureOutputWindow* New();
    vtkTypeMacro(CaptureOutputWindow, vtkOutputWindow);
    void DisplayText(const char*) override
    {
    }
    void DisplayErrorText(const char* text) override
    {
        if (t_vtk_error.empty())
            t_vtk_error = vtk_message_text(text);
    }
    void DisplayWarningText(const char*) override
    {
    }
    void DisplayGenericWarningText(const char*) override
    {
    }
    void DisplayDebugText(const char*) override
    {
    }

  protected:
    CaptureOutputWindow() = default;
};
vtkStandardNewMacro(CaptureOutputWindow);

/* Replaces VTK's output window for the whole process (it would print to stderr, in colour,
 * through its logger as well) by one that keeps the text for our messages. */
void quiet_vtk()
{
    static std::once_flag once;
    std::call_once(once, [] {
        vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
        vtkNew<CaptureOutputWindow> w;
        vtkOutputWindow::SetInstance(w);
    });
}

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

/* ---------------------------------------------------------------------------------------------
 * Names and files
 */
std::string lower_ext(const std::string& path)
{
    size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
        return std::string();
    std::string e = path.substr(dot);
    for (char& c : e)
        c = (char)std::tolower((unsigned char)c);
    return e;
}

tp_mesh_format format_of(const std::string& path)
{
    std::string e = lower_ext(path);
    return e == ".vtp"   ? TP_MESH_VTP
           : e == ".vtk" ? TP_MESH_VTK
           : e == ".vtm" ? TP_MESH_VTM
                         : TP_MESH_DEFAULT;
}

std::string dir_of(const std::string& path)
{
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string(".")
           : slash == 0               ? std::string("/")
                                      : path.substr(0, slash);
}

std::string base_of(const std::string& path)
{
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

/* path + ".tmp<pid>_<n>": unique per process and call. */
std::string temp_name(const std::string& path)
{
    static std::atomic<unsigned> counter{0};
    return path + ".tmp" + std::to_string((long)getpid()) + "_" + std::to_string(counter++);
}

/* Writes data into a file that must not exist yet; fsync'd and closed. Returns 0 or an errno
 * value; on failure the file is removed. */
int write_new_file(const std::string& name, const char* data, size_t size)
{
    int fd = open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0)
        return errno;
    int e = 0;
    size_t done = 0;
    while (done < size && !e) {
        ssize_t n = write(fd, data + done, std::min(size - done, (size_t)1 << 30));
        if (n > 0)
            done += (size_t)n;
        else if (n < 0 && errno != EINTR)
            e = errno;
        else if (n == 0)
            e = EIO;
    }
    struct stat st;
    if (!e && fstat(fd, &st) != 0)
        e = errno;
    if (!e && (uintmax_t)st.st_size != (uintmax_t)size)
        e = EIO; /* the file is not what was written */
    /* Delayed allocation: a full disk, a quota or NFS may only say so here. */
    if (!e && fsync(fd) != 0)
        e = errno;
    if (close(fd) != 0 && !e)
        e = errno;
    if (e)
        unlink(name.c_str());
    return e;
}

/* A new file of a unique temporary name beside path: 0 or errno. *tmp is set only on
 * success, so that it never names a file of someone else's. */
int write_temp_file(const std::string& path, const char* data, size_t size, std::string* tmp)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = temp_name(path);
        int e = write_new_file(name, data, size);
        if (e == 0)
            *tmp = name;
        if (e != EEXIST)
            return e;
    }
    return EEXIST;
}

/* Makes a new folder of a unique temporary name beside path: 0 or errno (*tmp as above). */
int make_temp_dir(const std::string& path, std::string* tmp)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = temp_name(path);
        if (mkdir(name.c_str(), 0777) == 0) {
            *tmp = name;
            return 0;
        }
        if (errno != EEXIST)
            return errno;
    }
    return EEXIST;
}

void sync_dir(const std::string& dir) /* best effort: the renames reach the disk */
{
    int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

/* Removes a file or folder we created, whatever happens to our caller. */
struct TempGuard {
    std::string name;
    ~TempGuard()
    {
        if (!name.empty()) {
            std::error_code ec;
            fs::remove_all(name, ec);
        }
    }
};

/* ---------------------------------------------------------------------------------------------
 * tp_mesh -> vtkPolyData
 */
void add_string(vtkFieldData* fd, const char* name, const char* value)
{
    if (!value || !*value) /* NULL or "": not known, no array */
        return;
    vtkNew<vtkStringArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    fd->AddArray(a);
}

/* Field data shared by the whole file (each .vtm block gets its own triangle_count). */
void add_field_data(vtkFieldData* fd, const tp_mesh* m, size_t triangle_count)
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

/* The triangles tris (all when NULL) and the points they use (all points when NULL: then
 * points is ignored, else points lists the mesh points in their new order and local holds the
 * triangles' corners as indices into it). */
vtkSmartPointer<vtkPolyData> build_polydata(const tp_mesh* m, const std::vector<size_t>* tris,
                                            const std::vector<size_t>* points,
                                            const std::vector<size_t>* local)
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

    vtkNew<vtkIdTypeArray> offsets, conn;
    offsets->SetNumberOfValues(nt + 1);
    conn->SetNumberOfValues(3 * nt);
    vtkIdType* o = offsets->GetPointer(0);
    vtkIdType* c = conn->GetPointer(0);
    for (vtkIdType i = 0; i <= nt; ++i)
        o[i] = 3 * i;
    for (vtkIdType i = 0; i < nt; ++i)
        for (int k = 0; k < 3; ++k)
            c[3 * i + k] = local ? (vtkIdType)(*local)[(size_t)(3 * i + k)]
                                 : (vtkIdType)m->triangles[3 * tri(i) + k];
    vtkNew<vtkCellArray> cells;
    cells->SetData(offsets, conn);
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
    add_field_data(pd->GetFieldData(), m, (size_t)nt);
    return pd;
}

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
    vtkSmartPointer<vtkPolyData> pd = build_polydata(m, nullptr, nullptr, nullptr);
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

    TempGuard guard;
    int e = write_temp_file(path, data, size, &guard.name);
    if (e == 0 && std::rename(guard.name.c_str(), path.c_str()) != 0)
        e = errno;
    if (e) /* the guard removes the temporary file */
        return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
    guard.name.clear(); /* renamed: nothing left to remove */
    sync_dir(dir_of(path));
    return TP_OK;
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
    const std::string dir = dir_of(path), name = base_of(path);
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
    int e = make_temp_dir(path, &guard.name);
    if (e)
        return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
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

        vtkSmartPointer<vtkPolyData> pd = build_polydata(m, &tris, &points, &local);
        std::string bytes, why;
        if (!vtp_bytes(pd, &bytes, &why))
            return fail(err, TP_ERR_BACKEND, "%s: VTK could not write the mesh: %s", path.c_str(),
                        why.c_str());
        const std::string file = prefix + "/" + prefix + "_" + std::to_string(block) + ".vtp";
        e = write_new_file(tmp + "/" + file, bytes.data(), bytes.size());
        if (e)
            return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
        index += "    <DataSet index=\"" + std::to_string(block) + "\" name=\"patch_" +
                 std::to_string(id) + "\" file=\"" + xml_attr(file) + "\"/>\n";
        ++block;
        begin = end;
    }
    index += "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    e = write_new_file(tmp + "/" + name, index.data(), index.size());
    if (e)
        return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
    const bool have_pieces = block > 0; /* no triangles: an index of no blocks, no folder */
    if (have_pieces)
        sync_dir(tmp + "/" + prefix);

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
    sync_dir(dir);
    return TP_OK; /* the guard removes tmp with the old pieces in it */
}

/* ---------------------------------------------------------------------------------------------
 * Reading back
 */
struct Loaded {
    std::vector<vtkSmartPointer<vtkPolyData>> blocks;
    vtkSmartPointer<vtkFieldData> composite_fields; /* .vtm only; may be empty */
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
        for (vtkIdType c = 0; c < npolys; ++c)
            tri += polys->GetCellSize(c) == 3;
        s->triangles += tri;
        s->other_cells += (size_t)(pd->GetNumberOfCells() - (vtkIdType)tri);

        vtkPointData* ptd = pd->GetPointData();
        vtkCellData* cd = pd->GetCellData();
        s->has_elevation &= ptd->GetAbstractArray("elevation_m") != nullptr;
        s->has_void_filled &= ptd->GetAbstractArray("void_filled") != nullptr;
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
    if (format != TP_MESH_VTM) {
        st = edge_counts(path, in.blocks.empty() ? nullptr : in.blocks[0].Get(), s, err);
    } else if (!in.blocks.empty()) {
        vtkNew<vtkAppendPolyData> append;
        for (vtkPolyData* pd : in.blocks)
            append->AddInputData(pd);
        vtkNew<vtkCleanPolyData> clean;
        clean->SetInputConnection(append->GetOutputPort());
        clean->PointMergingOn();
        clean->SetTolerance(0.0); /* exact: vtkMergePoints */
        clean->Update();
        st = edge_counts(path, clean->GetOutput(), s, err);
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
        if (tp_mesh_check_size(format, mesh->point_count, mesh->triangle_count, &size_err) !=
            TP_OK)
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
