/*
 * test_hud_lines.c - the words of the viewer's HUD (app/view/hud_lines.c), built from figures
 * with no scene and no GL (issue 29, 4.4 and 4.6): by default three short lines of what a user
 * on the ground needs (MGRS and latitude/longitude of the centre, its elevation, the eye's
 * height, heading and pitch, the scale, the grid spacing, the mode) and none of the engineering
 * figures; the error bound's field never says "inf" and says when it covers only what lies in
 * front of the near plane.
 */
#include "tp_test.h"

#include "hud_lines.h"

#include <string.h>

static tp_hud_ground mt_hood(void)
{
    return (tp_hud_ground){.centre = 1,
                           .centre_mgrs = "10T FR 02244 24440",
                           .centre_latlon = "45.36602N 121.69439W",
                           .centre_e = 602245,
                           .centre_n = 5024441,
                           .centre_elev_m = 3043.4,
                           .eye_m = 21926.8,
                           .above_m = NAN,
                           .heading_deg = 0,
                           .pitch_deg = -50,
                           .m_per_px = 39.6,
                           .grid_m = 10000,
                           .speed_mps = 120,
                           .exaggeration = 1};
}

static int lines_of(const char* s)
{
    int n = s[0] != '\0';
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

/* The longest line's length. */
static size_t widest(const char* s)
{
    size_t best = 0;
    while (*s) {
        size_t n = strcspn(s, "\n");
        best = n > best ? n : best;
        s += n + (s[n] == '\n');
    }
    return best;
}

static void expect_has(const char* text, const char* part)
{
    if (!strstr(text, part))
        FAIL("expected \"%s\" in the HUD:\n%s", part, text);
}

static void expect_lacks(const char* text, const char* part)
{
    if (strstr(text, part))
        FAIL("did not expect \"%s\" in the HUD:\n%s", part, text);
}

TEST(default_hud_is_three_short_lines_of_ground_information)
{
    tp_hud_ground g = mt_hood();
    char out[1024];
    size_t n = tp_hud_ground_text(&g, out, sizeof out);
    printf("%s\n", out);
    EXPECT_EQ_INT((int)strlen(out), (int)n);
    EXPECT_EQ_INT(3, lines_of(out));
    EXPECT_LE((double)widest(out), TP_HUD_LINE_MAX);
    expect_has(out, "10T FR 02244 24440");   /* MGRS of the centre */
    expect_has(out, "45.36602N 121.69439W"); /* latitude and longitude */
    expect_has(out, "elevation 3043 m");
    expect_has(out, "eye 21927 m");
    expect_has(out, "heading 0 deg");
    expect_has(out, "pitch -50 deg");
    expect_has(out, "scale 40 m/px");
    expect_has(out, "grid 10 km");
    expect_has(out, "FLY 120 m/s");
    expect_has(out, TP_HUD_DETAILS_KEY " details");
    /* the engineering figures are the details' */
    expect_lacks(out, "fps");
    expect_lacks(out, "CPU");
    expect_lacks(out, "triangles");
    expect_lacks(out, "level");
    expect_lacks(out, "error");
    expect_lacks(out, "UTM");
}

TEST(default_hud_variants_stay_short)
{
    char out[1024];
    /* orbiting, on the ground, exaggerated, frozen, details shown */
    tp_hud_ground g = mt_hood();
    g.orbit = 1;
    g.above_m = 2.0;
    g.eye_m = 1416;
    g.heading_deg = -90; /* west: 270 */
    g.m_per_px = 0.0068;
    g.grid_m = 1000;
    g.exaggeration = 1.5;
    g.details = 1;
    tp_hud_ground_text(&g, out, sizeof out);
    printf("%s\n", out);
    EXPECT_EQ_INT(3, lines_of(out));
    EXPECT_LE((double)widest(out), TP_HUD_LINE_MAX);
    expect_has(out, "ORBIT");
    expect_has(out, "2 m above ground");
    expect_has(out, "heading 270 deg");
    expect_has(out, "scale 0.0068 m/px");
    expect_has(out, "grid 1 km");
    expect_has(out, "heights x1.5");
    expect_has(out, TP_HUD_DETAILS_KEY " hide details");
    /* sky at the centre, no grid, no CRS */
    g = mt_hood();
    g.centre = 0;
    g.grid_m = 0;
    g.m_per_px = NAN;
    tp_hud_ground_text(&g, out, sizeof out);
    printf("%s\n", out);
    EXPECT_EQ_INT(3, lines_of(out));
    expect_has(out, "sky");
    expect_has(out, "scale -");
    expect_lacks(out, "grid");
    expect_lacks(out, "nan");
    g = mt_hood();
    g.centre_mgrs = g.centre_latlon = "";
    tp_hud_ground_text(&g, out, sizeof out);
    printf("%s\n", out);
    expect_has(out, "E 602245 N 5024441 (local)");
    /* a buffer too small is cut, NUL-terminated */
    char tiny[16];
    size_t n = tp_hud_ground_text(&g, tiny, sizeof tiny);
    EXPECT_EQ_INT(15, (int)n);
    EXPECT_EQ_INT(15, (int)strlen(tiny));
}

/* The bound's field: pixels of a store's nodes, with the nodes at the eye said; metres of a DEM
 * drawn whole; never "inf". */
TEST(error_bound_text_is_finite_and_says_what_it_covers)
{
    char out[256];
    tp_hud_bound b = {.kind = TP_HUD_BOUND_PX, .max = 0.997};
    tp_hud_bound_text(&b, out, sizeof out);
    EXPECT_EQ_STR("error bound max 1.00 px", out);
    b = (tp_hud_bound){.kind = TP_HUD_BOUND_PX, .max = 327.46, .near_nodes = 3};
    tp_hud_bound_text(&b, out, sizeof out);
    EXPECT_EQ_STR("error bound max 327 px (3 nodes at the eye: bounded in front of the near "
                  "plane)",
                  out);
    b.near_nodes = 1;
    tp_hud_bound_text(&b, out, sizeof out);
    expect_has(out, "(1 node at the eye");
    b = (tp_hud_bound){.kind = TP_HUD_BOUND_PX, .max = INFINITY};
    tp_hud_bound_text(&b, out, sizeof out);
    expect_lacks(out, "inf");
    EXPECT_EQ_STR("error bound unbounded", out);
    b = (tp_hud_bound){.kind = TP_HUD_BOUND_M, .max = 1.25, .rms_m = 0.5};
    tp_hud_bound_text(&b, out, sizeof out);
    EXPECT_EQ_STR("error bound max 1.25 m, RMS 0.50 m", out);
    b = (tp_hud_bound){.kind = TP_HUD_BOUND_NONE};
    tp_hud_bound_text(&b, out, sizeof out);
    EXPECT_EQ_STR("no error bound", out);
}

TEST(lengths_read_as_on_a_map)
{
    char out[32];
    tp_hud_length_text(1000, out, sizeof out);
    EXPECT_EQ_STR("1 km", out);
    tp_hud_length_text(10000, out, sizeof out);
    EXPECT_EQ_STR("10 km", out);
    tp_hud_length_text(100000, out, sizeof out);
    EXPECT_EQ_STR("100 km", out);
    tp_hud_length_text(12500, out, sizeof out);
    EXPECT_EQ_STR("12.5 km", out);
    tp_hud_length_text(250, out, sizeof out);
    EXPECT_EQ_STR("250 m", out);
}

#define TESTS(X)                                                                                   \
    X(default_hud_is_three_short_lines_of_ground_information)                                      \
    X(default_hud_variants_stay_short)                                                             \
    X(error_bound_text_is_finite_and_says_what_it_covers)                                          \
    X(lengths_read_as_on_a_map)
TP_TEST_MAIN(TESTS)
