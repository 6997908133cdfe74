/* format_read.hpp - what the readers of terrapatch's own files share: the store's (.tpt,
 * store_read.cpp) and the imagery pyramid's (.tpi, imagery_read.cpp). Both read with pread, so
 * that any number of threads may read one open file, and both headers end with a CRS, notes
 * and the CRC32 of all before (store_format.hpp, imagery_format.hpp). Private to io/. */
#pragma once

#include "io_util.hpp"
#include "range_file.hpp"
#include "store_format.hpp"

#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <unistd.h>

namespace tpio {

/* All of size bytes of fd at offset (pread, retried after EINTR), or an errno: EIO for a file
 * that ended early (it shrank). The file offset is not moved: threads may share fd. */
inline int read_at(int fd, void* buf, size_t size, uint64_t offset)
{
    uint8_t* p = static_cast<uint8_t*>(buf);
    while (size > 0) {
        const ssize_t got = pread(fd, p, size, (off_t)offset);
        if (got < 0) {
            if (errno == EINTR)
                continue;
            return errno;
        }
        if (got == 0)
            return EIO;
        p += got;
        size -= (size_t)got;
        offset += (uint64_t)got;
    }
    return 0;
}

/* The whole header, header_bytes from the start of file (path, file_bytes long), into head,
 * checked against the CRC32 in its last 4 bytes. TP_ERR_BAD_DATA for a file too short or a
 * checksum mismatch, TP_ERR_IO when it cannot be read; each message names path. */
inline tp_status read_header_bytes(const RangeFile& file, const char* path, uint64_t file_bytes,
                                   uint32_t header_bytes, std::vector<uint8_t>& head,
                                   tp_error* err)
{
    if (header_bytes > file_bytes)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, but the header alone takes %u", path,
                    file_bytes, header_bytes);
    head.resize(header_bytes);
    std::string why;
    if (!file.read(head.data(), head.size(), 0, &why))
        return fail(err, TP_ERR_IO, "%s: cannot read the header: %s", path, why.c_str());
    const uint8_t* h = head.data();
    const uint32_t head_crc = store::crc32_of(h, header_bytes - 4);
    if (head_crc != store::get_u32(h + header_bytes - 4))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged header: checksum mismatch in bytes 0..%u (stored 0x%08x, "
                    "computed 0x%08x)",
                    path, header_bytes - 1, store::get_u32(h + header_bytes - 4), head_crc);
    return TP_OK;
}

/* The CRS and notes of header h (header_bytes long): crs_bytes and notes_bytes of text after
 * its fixed part (fixed_bytes), then the CRC32. TP_ERR_BAD_DATA naming path when they do not
 * fill the header or hold a NUL byte; crs and notes are assigned before the NUL check. */
inline tp_status read_header_strings(const char* path, const uint8_t* h, size_t fixed_bytes,
                                     uint32_t header_bytes, uint32_t crs_bytes,
                                     uint32_t notes_bytes, std::string& crs, std::string& notes,
                                     tp_error* err)
{
    if ((uint64_t)fixed_bytes + crs_bytes + notes_bytes + 4 != header_bytes)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: bad header: CRS (%u bytes) and notes (%u bytes) do not fill its %u bytes",
                    path, crs_bytes, notes_bytes, header_bytes);
    crs.assign(reinterpret_cast<const char*>(h + fixed_bytes), crs_bytes);
    notes.assign(reinterpret_cast<const char*>(h + fixed_bytes + crs_bytes), notes_bytes);
    if (crs.find('\0') != std::string::npos || notes.find('\0') != std::string::npos)
        return fail(err, TP_ERR_BAD_DATA, "%s: bad header: a NUL byte inside the CRS or notes",
                    path);
    return TP_OK;
}

} // namespace tpio
