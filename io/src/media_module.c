/*
 * media_module.c - the image and mesh functions of tp_io.h, loaded when first called.
 *
 * OpenImageIO and VTK (io/src/image_read.cpp, image_rgba.cpp, texture.cpp, vtk_*.cpp) bring
 * ~170 shared libraries with them: linked into the terrapatch binary, the dynamic loader
 * spent ~0.45 s of every start on them (relocations and the libraries' initialisers), before
 * main(), whatever the command (docs/PERFORMANCE.md, "First frame"). In the binary those
 * sources are instead a module, libtp_io_media.so next to it (installed: in
 * <libdir>/terrapatch; CMakeLists.txt), and these
 * functions, with the signatures of tp_io.h, load it with dlopen on the first call and
 * forward to it. The module calls back into the binary (tp_core, the rest of tp_io), which
 * exports those symbols for it. The tests and tools link the whole of tp_io statically and
 * never see this file.
 *
 * A module that cannot be loaded is an installation fault, as a missing shared library is:
 * the functions that return a tp_status return TP_ERR_BACKEND with dlerror's message; the
 * others (tp_texture_destroy) print it and exit with 127, the loader's own status.
 */
#define _GNU_SOURCE
#include "tp_io.h"

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MODULE_NAME "libtp_io_media.so"

static pthread_once_t module_once = PTHREAD_ONCE_INIT;
static void* module_handle;
static char module_error[400];

/* Where an installed binary finds the module, relative to its own folder (CMakeLists.txt sets it
 * from the install layout: <bindir>/../lib/terrapatch). */
#ifndef TP_INSTALL_MODULE_REL
#define TP_INSTALL_MODULE_REL "../lib/terrapatch"
#endif

/* The module beside the executable (/proc/self/exe: the build tree), else in the installed
 * layout relative to it, else wherever dlopen finds the name. */
static void module_load(void)
{
    char exe[PATH_MAX], path[PATH_MAX + sizeof TP_INSTALL_MODULE_REL + sizeof MODULE_NAME + 2];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    char* slash = NULL;
    if (n > 0) {
        exe[n] = '\0';
        slash = strrchr(exe, '/');
    }
    if (slash) {
        *slash = '\0';
        const char* rel[] = {".", TP_INSTALL_MODULE_REL};
        for (size_t i = 0; i < sizeof rel / sizeof rel[0] && !module_handle; i++) {
            snprintf(path, sizeof path, "%s/%s/%s", exe, rel[i], MODULE_NAME);
            if (access(path, F_OK) != 0)
                continue;
            module_handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
            const char* e = module_handle ? NULL : dlerror();
            if (e && !module_error[0]) /* a module that is there but fails to load says why */
                snprintf(module_error, sizeof module_error,
                         "cannot load the image and mesh module: %s", e);
        }
    }
    if (!module_handle)
        module_handle = dlopen(MODULE_NAME, RTLD_NOW | RTLD_LOCAL);
    if (module_handle) {
        module_error[0] = '\0';
    } else if (!module_error[0]) {
        const char* e = dlerror();
        snprintf(module_error, sizeof module_error, "cannot load the image and mesh module: %s",
                 e ? e : MODULE_NAME);
    }
}

/* The module's function called name, or NULL with the reason in module_error. */
static void* module_symbol(const char* name)
{
    pthread_once(&module_once, module_load);
    if (!module_handle)
        return NULL;
    void* f = dlsym(module_handle, name);
    if (!f)
        snprintf(module_error, sizeof module_error, "%s: %s", MODULE_NAME, dlerror());
    return f;
}

/* Defines tp_status name params, which looks the module's function up once (the pointer is
 * stored atomically: any thread may call first) and calls it with args; err is the argument
 * that receives the message when the module cannot be loaded. */
#define FORWARD(name, params, args, err)                                                           \
    tp_status name params                                                                          \
    {                                                                                              \
        typedef tp_status(*fn_type) params;                                                        \
        static fn_type fn;                                                                         \
        fn_type f = __atomic_load_n(&fn, __ATOMIC_ACQUIRE);                                        \
        if (!f) {                                                                                  \
            f = (fn_type)module_symbol(#name);                                                     \
            if (!f)                                                                                \
                return tp_error_set(err, TP_ERR_BACKEND, "%s", module_error);                      \
            __atomic_store_n(&fn, f, __ATOMIC_RELEASE);                                            \
        }                                                                                          \
        return f args;                                                                             \
    }

FORWARD(tp_dem_read_image,
        (const char* path, const tp_image_options* options, tp_dem** out, tp_error* err),
        (path, options, out, err), err)
FORWARD(tp_image_output_check, (const char* path, tp_error* err), (path, err), err)
FORWARD(tp_image_write_rgba, (const char* path, int w, int h, const uint8_t* rgba, tp_error* err),
        (path, w, h, rgba, err), err)
FORWARD(tp_image_read_rgba, (const char* path, int* w, int* h, uint8_t** rgba, tp_error* err),
        (path, w, h, rgba, err), err)
FORWARD(tp_texture_build,
        (const char* path, const tp_render_grid* grid, int max_size, tp_texture** out,
         tp_error* err),
        (path, grid, max_size, out, err), err)
FORWARD(tp_mesh_inspect, (const char* path, tp_mesh_summary* out, tp_error* err), (path, out, err),
        err)
FORWARD(tp_mesh_read_points, (const char* path, double** xyz, size_t* count, tp_error* err),
        (path, xyz, count, err), err)
FORWARD(tp_mesh_check_size,
        (tp_mesh_format format, size_t point_count, size_t triangle_count, tp_error* err),
        (format, point_count, triangle_count, err), err)
FORWARD(tp_mesh_write,
        (const char* path, tp_mesh_format format, const tp_mesh* mesh, tp_error* err),
        (path, format, mesh, err), err)
FORWARD(tp_mesh_write_pieces,
        (const char* path, const tp_mesh* fields, size_t triangle_total, size_t piece_count,
         tp_mesh_piece_fn piece_fn, void* user, tp_error* err),
        (path, fields, triangle_total, piece_count, piece_fn, user, err), err)

void tp_texture_destroy(tp_texture* tex)
{
    if (!tex) /* nothing to free, and no reason to load the module */
        return;
    /* a texture exists only if tp_texture_build loaded the module */
    void (*f)(tp_texture*) = (void (*)(tp_texture*))module_symbol("tp_texture_destroy");
    if (!f) {
        fprintf(stderr, "terrapatch: %s\n", module_error);
        exit(127);
    }
    f(tex);
}
