/*
 * fuzz_mesh_inspect.c - libFuzzer entry point for tp_mesh_inspect (io/src/vtk_mesh_inspect.cpp),
 * the VTK reader the tests and `export --check` read meshes back with (VTK's XML PolyData,
 * and multiblock readers). The first byte picks the extension, so the reader; the rest is the
 * file, written to a private temporary folder, as VTK's readers take a path.
 *
 * Not fuzzed: the legacy .vtk reader. VTK 9.1's vtkPolyDataReader dereferences NULL on a
 * field-data array cut short (after 13 executions: SEGV in vtkPolyDataReader::ReadMeshSimple,
 * libvtkIOLegacy-9.1.so.1+0x68ad0; the input is tests/fuzz/third_party/
 * vtk_legacy_polydata_reader_segv.vtk.bin, whose first byte is the pick). That is VTK's to fix
 * and we cannot check a legacy file for it short of parsing it ourselves; tp_mesh_inspect
 * reads back files terrapatch itself wrote (tests, `export --check`), not files from outside.
 *
 * Skipped: XML files with a type="..." that VTK does not know, or an array element without a
 * type. VTK 9.1's XML reader dereferences NULL for a DataArray of an unknown type ("Int33") or
 * none (SEGV in vtkXMLReader::ReadXMLInformation, libvtkIOXML-9.1.so.1+0x98753; the inputs
 * are tests/fuzz/third_party/vtk_xml_unknown_array_type_segv.vtp.bin and
 * vtk_xml_array_without_type_segv.vtp.bin).
 */
#include "fuzz_util.h"
#include "tp_io.h"

#include <string.h>

/* 1 if every type="..." in data is a VTK XML data set or array type. */
static int types_known(const uint8_t* data, size_t size)
{
    static const char* const known[] = {"PolyData", "vtkMultiBlockDataSet",
                                        "Int8",     "UInt8",
                                        "Int16",    "UInt16",
                                        "Int32",    "UInt32",
                                        "Int64",    "UInt64",
                                        "Float32",  "Float64",
                                        "String"};
    static const char key[] = "type=\"";
    const size_t klen = sizeof key - 1;
    for (size_t i = 0; i + klen <= size; ++i) {
        if (memcmp(data + i, key, klen) != 0)
            continue;
        const uint8_t* v = data + i + klen;
        const uint8_t* end = memchr(v, '"', size - (size_t)(v - data));
        if (!end)
            return 0;
        size_t n = (size_t)(end - v), k;
        for (k = 0; k < sizeof known / sizeof known[0]; ++k)
            if (strlen(known[k]) == n && !memcmp(v, known[k], n))
                break;
        if (k == sizeof known / sizeof known[0])
            return 0;
    }
    return 1;
}

/* 1 if every <DataArray and <Array element of data has a type="..." attribute. */
static int arrays_typed(const uint8_t* data, size_t size)
{
    static const char* const tags[] = {"<DataArray", "<Array"};
    for (size_t i = 0; i < size; ++i) {
        for (int t = 0; t < 2; ++t) {
            size_t n = strlen(tags[t]);
            if (i + n > size || memcmp(data + i, tags[t], n) != 0)
                continue;
            const uint8_t* end = memchr(data + i, '>', size - i);
            size_t len = end ? (size_t)(end - (data + i)) : size - i;
            int typed = 0;
            for (size_t k = i; k + 7 <= i + len && !typed; ++k)
                typed = !memcmp(data + k, " type=\"", 7);
            if (!typed)
                return 0;
        }
    }
    return 1;
}

static const char* const names[] = {"m.vtp", "m.vtm"}; /* no "m.vtk": see above */

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1 || !types_known(data + 1, size - 1) || !arrays_typed(data + 1, size - 1))
        return 0;
    const char* path = tp_fuzz_write_file(names[data[0] % 2], data + 1, size - 1);
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
