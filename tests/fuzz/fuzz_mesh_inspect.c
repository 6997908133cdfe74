/*
 * fuzz_mesh_inspect.c - libFuzzer entry point for tp_mesh_inspect (io/src/vtk_mesh_inspect.cpp),
 * the VTK reader the tests and `export --check` read meshes back with (VTK's XML PolyData,
 * legacy and multiblock readers). The first byte picks the extension, so the reader; the rest
 * is the file, written to a private temporary folder, as VTK's readers take a path.
 */
#include "fuzz_util.h"
#include "tp_io.h"

#include <string.h>

static const char* const names[] = {"m.vtp", "m.vtk", "m.vtm"};

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    const char* path = tp_fuzz_write_file(names[data[0] % 3], data + 1, size - 1);
    if (!path)
        return 0;
    tp_mesh_summary summary;
    memset(&summary, 0xAB, sizeof summary);
    tp_mesh_summary untouched = summary;
    tp_error err = {{0}};
    tp_status s = tp_mesh_inspect(path, &summary, &err);
    if (s != TP_OK) {
        TP_FUZZ_CHECK(!memcmp(&summary, &untouched, sizeof summary), "status %d wrote *out",
                      (int)s);
        TP_FUZZ_CHECK(err.message[0] != '\0', "status %d without a message", (int)s);
    }
    return 0;
}
