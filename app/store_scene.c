/* store_scene.c - a built store opened for drawing (see store_scene.h). */
#define _POSIX_C_SOURCE 200809L
#include "store_scene.h"

#include "cli.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

int tp_is_store_path(const char* path)
{
    static const unsigned char magic[8] = {0x89, 'T', 'P', 'T', '\r', '\n', 0x1A, '\n'};
    unsigned char head[8];
    struct stat st;
    /* never open a FIFO or a device to look: it could block; the readers refuse those */
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return 0;
    FILE* f = fopen(path, "rb");
    if (!f)
        return 0;
    size_t got = fread(head, 1, sizeof head, f);
    fclose(f);
    return got == sizeof head && memcmp(head, magic, sizeof magic) == 0;
}

int tp_store_scene_open(const char* path, tp_store_scene* sc)
{
    memset(sc, 0, sizeof *sc);
    sc->path = path;
    tp_error err = {{0}};
    tp_status s = tp_store_open(path, &sc->store, &err);
    if (s == TP_OK) {
        tp_store_get_info(sc->store, &sc->info);
        s = tp_tree_create_from_store(sc->store, &sc->tree, &err);
    }
    if (s == TP_OK) {
        tp_tree_get_info(sc->tree, &sc->tree_info);
        s = tp_georef_create(sc->info.header.crs_wkt, sc->info.header.geotransform, &sc->georef,
                             &err);
    }
    if (s != TP_OK) {
        /* the store's messages name the file; the others do not */
        if (strstr(err.message, path))
            fprintf(stderr, "terrapatch: %s\n", err.message);
        else
            fprintf(stderr, "terrapatch: %s: %s\n", path,
                    err.message[0] ? err.message : tp_status_str(s));
        tp_store_scene_close(sc);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

int tp_store_scene_stream(tp_store_scene* sc, const tp_stream_options* o)
{
    char msg[600];
    sc->stream = tp_stream_create(sc->store, sc->tree, o, msg, sizeof msg);
    if (!sc->stream) {
        if (strstr(msg, sc->path))
            fprintf(stderr, "terrapatch: %s\n", msg);
        else
            fprintf(stderr, "terrapatch: %s: %s\n", sc->path, msg);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

void tp_store_scene_close(tp_store_scene* sc)
{
    tp_stream_destroy(sc->stream); /* detaches every block before the tree goes */
    tp_georef_destroy(sc->georef);
    tp_tree_destroy(sc->tree);
    tp_store_close(sc->store);
    memset(sc, 0, sizeof *sc);
}
