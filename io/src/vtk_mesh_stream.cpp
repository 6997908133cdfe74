/* vtk_mesh_stream.cpp - a .vtp written a piece at a time (tp_mesh_write_pieces): export --full of
 * a map of any size in bounded memory.
 *
 * VTK's own streaming: vtkXMLPolyDataWriter with NumberOfPieces = N asks its input for piece
 * 0, 1, ... N - 1 in turn through the pipeline (UPDATE_PIECE_NUMBER) and writes each before
 * asking for the next. Our input is a vtkPolyDataAlgorithm that answers each request with the
 * caller's piece (tp_mesh_piece_fn), so only one piece is ever in memory.
 *
 * The data are appended raw (not base64), compressed: the writer puts the header first with
 * placeholders and seeks back to fill in each piece's counts and offsets, so it writes to a
 * seekable stream. That stream is ours: a streambuf over tp_file_writer (atomic_write.cpp), so
 * the temporary file, every write checked with its errno, the signal flag and the rename into
 * place are the same as for every other file; appended mode is also the mode in which VTK 9.1
 * survives a failing stream (vtk_mesh_write.cpp says why inline binary does not).
 */
#include "io_util.hpp"
#include "tp_io.h"
#include "vtk_util.hpp"

#include <vtkErrorCode.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkPolyDataAlgorithm.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkXMLPolyDataWriter.h>

#include <climits>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

using tpio::fail;

namespace {

/* A seekable output stream over a tp_file_writer: bytes go to a buffer, which is appended, or
 * written over what is there after a seek back (tp_file_rewrite). The first failure sticks:
 * every later write fails and err keeps the message (the file is gone already). */
class FileBuf : public std::streambuf {
  public:
    explicit FileBuf(tp_file_writer* w) : w_(w), buf_((size_t)1 << 20)
    {
        setp(buf_.data(), buf_.data() + buf_.size());
    }
    bool failed() const
    {
        return failed_;
    }
    const tp_error& error() const
    {
        return err_;
    }

  protected:
    int_type overflow(int_type c) override
    {
        if (!flush())
            return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }
    int sync() override
    {
        return flush() ? 0 : -1;
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir,
                     std::ios_base::openmode which) override
    {
        if (!(which & std::ios_base::out) || !flush())
            return pos_type(off_type(-1));
        const int64_t from = dir == std::ios_base::beg   ? 0
                             : dir == std::ios_base::cur ? (int64_t)pos_
                                                         : (int64_t)size_;
        const int64_t to = from + (int64_t)off;
        if (to < 0 || (uint64_t)to > size_)
            return pos_type(off_type(-1));
        pos_ = (uint64_t)to;
        return pos_type(off_type(to));
    }
    pos_type seekpos(pos_type p, std::ios_base::openmode which) override
    {
        return seekoff(off_type(p), std::ios_base::beg, which);
    }

  private:
    /* The buffer to the file at pos_: over what is there, then appended. */
    bool flush()
    {
        if (failed_)
            return false;
        const char* d = pbase();
        size_t n = (size_t)(pptr() - pbase());
        setp(buf_.data(), buf_.data() + buf_.size());
        if (pos_ < size_ && n) {
            const size_t k = n < size_ - pos_ ? n : (size_t)(size_ - pos_);
            if (tp_file_rewrite(w_, pos_, d, k, &err_) != TP_OK)
                return failed_ = true, false;
            pos_ += k;
            d += k;
            n -= k;
        }
        if (n) {
            if (tp_file_append(w_, d, n, &err_) != TP_OK)
                return failed_ = true, false;
            pos_ += n;
            size_ += n;
        }
        return true;
    }

    tp_file_writer* w_;
    std::vector<char> buf_;
    uint64_t pos_ = 0;  /* the file offset of the buffer's first byte */
    uint64_t size_ = 0; /* bytes in the file */
    bool failed_ = false;
    tp_error err_{};
};

/* The pipeline's source: piece i of the caller's mesh when the writer asks for piece i. After a
 * failure every piece is an empty one with the same arrays (the writer then runs to its end
 * quickly, and the file is thrown away). */
class PieceSource : public vtkPolyDataAlgorithm {
  public:
    static PieceSource* New();
    vtkTypeMacro(PieceSource, vtkPolyDataAlgorithm);

    const tp_mesh* fields = nullptr;
    size_t triangle_total = 0, piece_count = 0, pieces_made = 0;
    tp_mesh_piece_fn fn = nullptr;
    void* user = nullptr;
    tp_status status = TP_OK;
    tp_error err{};
    std::string path;

  protected:
    PieceSource()
    {
        SetNumberOfInputPorts(0);
    }

    int RequestInformation(vtkInformation*, vtkInformationVector**,
                           vtkInformationVector* out) override
    {
        out->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
        return 1;
    }

    int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* out) override
    {
        vtkInformation* info = out->GetInformationObject(0);
        vtkPolyData* output = vtkPolyData::GetData(info);
        const int piece = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
        tp_mesh m = *fields;
        if (status == TP_OK)
            make(piece, &m);
        if (status != TP_OK) {
            static const double no_d = 0;
            static const uint8_t no_u8 = 0;
            static const int32_t no_i32 = 0;
            static const uint64_t no_u64 = 0;
            m.point_count = m.triangle_count = 0;
            m.xyz = m.elevation_m = m.max_error_m = &no_d;
            m.void_filled = m.lod = &no_u8;
            m.patch_id = &no_i32;
            m.triangles = &no_u64;
        }
        output->ShallowCopy(tpvtk::build_polydata(&m, nullptr, nullptr, nullptr, triangle_total));
        return 1;
    }

  private:
    void make(int piece, tp_mesh* m)
    {
        if (piece < 0 || (size_t)piece != pieces_made || (size_t)piece >= piece_count) {
            status = fail(&err, TP_ERR_INVALID_ARG, "%s: VTK asked for piece %d of %zu out of turn",
                          path.c_str(), piece, piece_count);
            return;
        }
        pieces_made++;
        if ((status = fn(user, (size_t)piece, m, &err)) != TP_OK)
            return;
        if (m->point_count >= INT32_MAX || m->triangle_count >= INT32_MAX / 3 ||
            (m->point_count && !m->xyz) || (m->triangle_count && !m->triangles) ||
            !m->elevation_m || !m->void_filled || !m->patch_id || !m->lod || !m->max_error_m) {
            status = fail(&err, TP_ERR_INVALID_ARG,
                          "%s: piece %d: %zu points, %zu triangles, or an array missing (each "
                          "piece holds fewer than 2^31 of each and every array)",
                          path.c_str(), piece, m->point_count, m->triangle_count);
            return;
        }
        for (size_t i = 0; i < 3 * m->triangle_count; ++i)
            if (m->triangles[i] >= m->point_count) {
                status = fail(&err, TP_ERR_INVALID_ARG,
                              "%s: piece %d, triangle %zu: expected point indices below %zu, got "
                              "%llu",
                              path.c_str(), piece, i / 3, m->point_count,
                              (unsigned long long)m->triangles[i]);
                return;
            }
    }
};
vtkStandardNewMacro(PieceSource);

/* vtkXMLPolyDataWriter that writes to our stream (VTK 9.1 keeps the stream member protected:
 * set before Write, it is used instead of a file and left open). */
class StreamWriter : public vtkXMLPolyDataWriter {
  public:
    static StreamWriter* New();
    vtkTypeMacro(StreamWriter, vtkXMLPolyDataWriter);
    void UseStream(std::ostream* os)
    {
        this->Stream = os;
    }
};
vtkStandardNewMacro(StreamWriter);

} // namespace

extern "C" tp_status tp_mesh_write_pieces(const char* path, const tp_mesh* fields,
                                          size_t triangle_total, size_t piece_count,
                                          tp_mesh_piece_fn piece_fn, void* user, tp_error* err)
{
    if (!path || !*path || !fields || !piece_fn || piece_count == 0)
        return fail(err, TP_ERR_INVALID_ARG,
                    "mesh: bad arguments (path, fields or piece function NULL, or no piece)");
    try {
        const std::string p = path;
        if (tpvtk::format_of(p) != TP_MESH_VTP)
            return fail(err, TP_ERR_INVALID_ARG,
                        "%s: a mesh written in pieces is a .vtp (VTK XML PolyData)", path);
        if (piece_count > (size_t)INT_MAX)
            return fail(err, TP_ERR_INVALID_ARG, "%s: %zu pieces: VTK numbers them in an int", path,
                        piece_count);
        tp_file_writer* fw = nullptr;
        tp_status s = tp_file_begin(path, &fw, err);
        if (s != TP_OK)
            return s;
        /* whatever happens before the commit (an exception too), the temporary file goes */
        struct Abort {
            tp_file_writer*& w;
            ~Abort()
            {
                tp_file_abort(w);
            }
        } abort_guard{fw};
        tpvtk::VtkErrors errors;
        vtkNew<PieceSource> src;
        src->fields = fields;
        src->triangle_total = triangle_total;
        src->piece_count = piece_count;
        src->fn = piece_fn;
        src->user = user;
        src->path = p;
        FileBuf buf(fw);
        std::ostream os(&buf);
        {
            vtkNew<StreamWriter> w;
            w->SetInputConnection(src->GetOutputPort());
            w->SetNumberOfPieces((int)piece_count);
            w->SetDataModeToAppended();
            w->EncodeAppendedDataOff();
            w->SetCompressorTypeToZLib();
            w->SetHeaderTypeToUInt64();
            w->SetIdTypeToInt32(); /* each piece numbers its own points: below 2^31 */
            w->UseStream(&os);
            w->Write();
            os.flush();
            if (src->status == TP_OK && !buf.failed() &&
                (w->GetErrorCode() != vtkErrorCode::NoError || errors.any()))
                s = fail(err, TP_ERR_BACKEND, "%s: VTK could not write the mesh: %s", path,
                         errors.any() ? errors.text()
                                      : vtkErrorCode::GetStringFromErrorCode(w->GetErrorCode()));
        }
        if (src->status != TP_OK) {
            *err = src->err;
            s = src->status;
        } else if (buf.failed()) {
            *err = buf.error();
            s = TP_ERR_IO;
        } else if (s == TP_OK && src->pieces_made != piece_count) {
            s = fail(err, TP_ERR_BACKEND, "%s: VTK asked for %zu of the %zu pieces", path,
                     src->pieces_made, piece_count);
        }
        if (s != TP_OK)
            return s;
        tp_file_writer* done = fw;
        fw = nullptr; /* the commit frees it, whatever happens */
        return tp_file_commit(done, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}
