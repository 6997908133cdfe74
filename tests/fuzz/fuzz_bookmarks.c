/*
 * fuzz_bookmarks.c - libFuzzer entry point for the viewer's bookmarks file (app/scene/bookmarks.c):
 * one line read by tp_bookmark_parse_line, as tp_bookmarks_load reads each line of the file.
 *
 * Input: the line (any bytes; cut at the first NUL or line break, as the file reader does).
 * Checks: a bookmark read has a name (trimmed, no line break, not "--camera"), five finite
 * numbers and, with --camera-geo, a latitude in [-90, 90]; written back with tp_bookmark_format
 * it reads back with the same name and kind; a blank or '#' line writes nothing; a malformed
 * line writes nothing and says why.
 */
#include "bookmarks.h"
#include "fuzz_util.h"

#include <math.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    char line[1024];
    size_t n = 0;
    while (n < size && n + 1 < sizeof line && data[n] != '\0' && data[n] != '\n')
        n++;
    memcpy(line, data, n);
    line[n] = '\0';
    tp_bookmark b, before;
    memset(&b, 0x55, sizeof b);
    before = b;
    tp_error why;
    memset(&why, 0, sizeof why);
    int r = tp_bookmark_parse_line(line, &b, &why);
    TP_FUZZ_CHECK(r >= -1 && r <= 1, "returned %d", r);
    if (r <= 0) {
        TP_FUZZ_CHECK(memcmp(&b, &before, sizeof b) == 0, "no bookmark but the output written");
        TP_FUZZ_CHECK(r == 0 || why.message[0], "malformed without a reason");
        return 0;
    }
    TP_FUZZ_CHECK(memchr(b.name, '\0', sizeof b.name) && b.name[0], "no name");
    TP_FUZZ_CHECK(!strchr(b.name, '\n') && !strchr(b.name, '\r'), "a line break in the name");
    TP_FUZZ_CHECK(b.name[0] != ' ' && b.name[strlen(b.name) - 1] != ' ', "name not trimmed");
    TP_FUZZ_CHECK(!strstr(b.name, "--camera"), "'--camera' in the name '%s'", b.name);
    for (int i = 0; i < 5; i++)
        TP_FUZZ_CHECK(isfinite(b.v[i]), "value %d is %g", i, b.v[i]);
    TP_FUZZ_CHECK(!b.geo || (b.v[0] >= -90 && b.v[0] <= 90), "latitude %g", b.v[0]);
    char text[2048];
    tp_bookmark_format(&b, text, sizeof text);
    tp_bookmark back;
    TP_FUZZ_CHECK(tp_bookmark_parse_line(text, &back, &why) == 1,
                  "'%s' written back does not read: %s", text, why.message);
    TP_FUZZ_CHECK(strcmp(back.name, b.name) == 0 && back.geo == b.geo,
                  "'%s' reads back as '%s' (%d)", text, back.name, back.geo);
    return 0;
}
