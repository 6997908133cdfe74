/* image_name.cpp - tp_is_heightmap_image: which paths the OpenImageIO reader takes, by name.
 * Kept apart from image_read.cpp so that asking does not load OpenImageIO (the media module,
 * io/src/media_module.c). */
#include "tp_io.h"

#include <cstring>
#include <strings.h>

/* C string functions only: nothing can throw; NULL is not an image. */
extern "C" int tp_is_heightmap_image(const char* path)
{
    static const char* const exts[] = {".png", ".jpg", ".jpeg", ".exr", ".pgm", ".ppm",
                                       ".tga", ".bmp", ".hdr", ".webp"};
    size_t len = path ? std::strlen(path) : 0;
    for (const char* e : exts) {
        size_t el = std::strlen(e);
        if (len > el && strcasecmp(path + len - el, e) == 0)
            return 1;
    }
    return 0;
}
