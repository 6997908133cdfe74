/*
 * test_bookmarks.c - the viewer's named camera views in their text file (app/scene/bookmarks.c):
 * round trip through the file, names with spaces, a corrupted line named by file and line, a
 * missing file as no bookmarks, an atomic save that leaves the older file on failure.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_io.h"

#define TP_TMP_PREFIX "tp_bookmarks_"
#include "tp_test_tmp.h"

#include "tp_test_child.h"

#include "bookmarks.h"

#include <stdio.h>
#include <string.h>

static void write_text(const char* path, const char* text)
{
    FILE* f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fputs(text, f);
    fclose(f);
}

static void read_text(const char* path, char* out, size_t cap)
{
    FILE* f = fopen(path, "r");
    ASSERT_TRUE(f != NULL);
    size_t n = fread(out, 1, cap - 1, f);
    out[n] = '\0';
    fclose(f);
}

TEST(round_trip_keeps_names_with_spaces_and_values)
{
    const char* dir = make_tmp_dir();
    char path[1024];
    tp_error err = {{0}};
    snprintf(path, sizeof path, "%s/sub/dir/hood.tif.bookmarks", dir); /* folders made */
    tp_bookmarks b = {0};
    tp_bookmark a = {.name = "OP north ridge", .geo = 1,
                     .v = {45.373456789, -121.695123456, 3200.25, 20.5, -30.75}};
    tp_bookmark c = {.name = "view 3", .geo = 0, .v = {600123.456, 5024000.125, 2100, 0, -90}};
    ASSERT_TRUE(tp_bookmarks_set(&b, &a, &err));
    ASSERT_TRUE(tp_bookmarks_set(&b, &c, &err));
    ASSERT_TRUE(tp_bookmarks_save(path, &b, &err));
    tp_bookmarks r;
    ASSERT_TRUE(tp_bookmarks_load(path, &r, &err));
    ASSERT_EQ_INT((int)r.count, 2);
    EXPECT_EQ_STR("OP north ridge", r.items[0].name);
    EXPECT_EQ_INT(r.items[0].geo, 1);
    EXPECT_NEAR(r.items[0].v[0], 45.373456789, 1e-12);
    EXPECT_NEAR(r.items[0].v[1], -121.695123456, 1e-12);
    EXPECT_NEAR(r.items[0].v[2], 3200.25, 1e-9);
    EXPECT_NEAR(r.items[0].v[3], 20.5, 1e-9);
    EXPECT_NEAR(r.items[0].v[4], -30.75, 1e-9);
    EXPECT_EQ_STR("view 3", r.items[1].name);
    EXPECT_EQ_INT(r.items[1].geo, 0);
    EXPECT_NEAR(r.items[1].v[0], 600123.456, 1e-9);
    EXPECT_NEAR(r.items[1].v[4], -90, 1e-12);
    /* the lines as documented */
    char text[2048];
    read_text(path, text, sizeof text);
    EXPECT_CONTAINS(text, "\nOP north ridge --camera-geo 45.373456789,-121.695123456,3200.25,20.50,-30.75\n");
    EXPECT_CONTAINS(text, "\nview 3 --camera 600123.456,5024000.125,2100.00,0.00,-90.00\n");
    /* set replaces a name in place, keeping the order */
    tp_bookmark a2 = a;
    a2.v[2] = 999;
    ASSERT_TRUE(tp_bookmarks_set(&r, &a2, &err));
    ASSERT_EQ_INT((int)r.count, 2);
    EXPECT_NEAR(tp_bookmarks_find(&r, "OP north ridge")->v[2], 999, 0);
    EXPECT_TRUE(tp_bookmarks_find(&r, "OP north") == NULL);
    char names[256];
    tp_bookmarks_names(&r, names, sizeof names);
    EXPECT_EQ_STR("'OP north ridge', 'view 3'", names);
    tp_bookmarks_free(&r);
    tp_bookmarks_free(&b);
}

TEST(hand_written_file_with_comments_blank_lines_and_spaces)
{
    const char* dir = make_tmp_dir();
    char path[1024];
    tp_error err = {{0}};
    snprintf(path, sizeof path, "%s/b.bookmarks", dir);
    write_text(path, "# my views\n\n   summit   --camera-geo  46.85, -121.76 ,4500,180,-45\r\n"
                     "\tcrater rim --camera 1,2,3,4,5");
    tp_bookmarks r;
    ASSERT_TRUE(tp_bookmarks_load(path, &r, &err));
    ASSERT_EQ_INT((int)r.count, 2);
    EXPECT_EQ_STR("summit", r.items[0].name);
    EXPECT_NEAR(r.items[0].v[1], -121.76, 1e-12);
    EXPECT_NEAR(r.items[0].v[3], 180, 0);
    EXPECT_EQ_STR("crater rim", r.items[1].name);
    EXPECT_EQ_INT(r.items[1].geo, 0);
    EXPECT_NEAR(r.items[1].v[4], 5, 0);
    tp_bookmarks_free(&r);
}

TEST(corrupted_line_names_file_and_line)
{
    const char* dir = make_tmp_dir();
    char path[1024], want[1100];
    tp_error err = {{0}};
    snprintf(path, sizeof path, "%s/bad.bookmarks", dir);
    const char* bad[][2] = {
        {"a --camera-geo 45,7,100,0,-30\nb --camera-geo 45,7,100,0\n", "expected five numbers"},
        {"a --camera-geo 45,7,100,0,-30\n\n# c\nb --camera-geo 45,7,1x0,0,-30\n", "'45,7,1x0,0,-30"},
        {"a --camera-geo 45,7,100,0,-30\njust some words\n", "expected NAME --camera-geo"},
        {"a --camera-geo 45,7,100,0,-30\n--camera 1,2,3,4,5\n", "no name"},
        {"a --camera-geo 45,7,100,0,-30\nz --camera-geo 95,7,100,0,-30\n", "latitude 95"},
        {"a --camera-geo 45,7,100,0,-30\nz --camera-geo nan,7,100,0,-30\n", "five numbers"},
        {"a --camera-geo 45,7,100,0,-30\nz --camerax 1,2,3,4,5\n", "--camera-geo or --camera"},
    };
    const int line_of[] = {2, 4, 2, 2, 2, 2, 2};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        write_text(path, bad[i][0]);
        tp_bookmarks r = {(tp_bookmark*)1, 7};
        EXPECT_FALSE(tp_bookmarks_load(path, &r, &err));
        snprintf(want, sizeof want, "%s:%d: ", path, line_of[i]);
        EXPECT_CONTAINS(err.message, want);
        EXPECT_CONTAINS(err.message, bad[i][1]);
        EXPECT_TRUE(r.items == NULL && r.count == 0);
    }
}

TEST(missing_file_is_no_bookmarks_and_unreadable_is_an_error)
{
    const char* dir = make_tmp_dir();
    char path[1024];
    tp_error err = {{0}};
    snprintf(path, sizeof path, "%s/none.bookmarks", dir);
    tp_bookmarks r;
    ASSERT_TRUE(tp_bookmarks_load(path, &r, &err));
    EXPECT_EQ_INT((int)r.count, 0);
    char names[64];
    tp_bookmarks_names(&r, names, sizeof names);
    EXPECT_EQ_STR("none", names);
    /* a folder where the file should be */
    EXPECT_FALSE(tp_bookmarks_load(dir, &r, &err));
    EXPECT_CONTAINS(err.message, dir);
    EXPECT_CONTAINS(err.message, "cannot open: Is a directory");
}

TEST(names_that_would_not_read_back_are_refused)
{
    tp_bookmarks b = {0};
    tp_error err = {{0}};
    const char* names[] = {"", " lead", "trail ", "# hash", "a --camera b", "two\nlines"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        tp_bookmark bm = {.geo = 1, .v = {45, 7, 100, 0, -30}};
        snprintf(bm.name, sizeof bm.name, "%s", names[i]);
        EXPECT_FALSE(tp_bookmarks_set(&b, &bm, &err));
        EXPECT_CONTAINS(err.message, "cannot be kept");
    }
    EXPECT_EQ_INT((int)b.count, 0);
}

TEST(failed_save_names_the_file_and_leaves_what_was_there)
{
    const char* dir = make_tmp_dir();
    char path[1024], before[256], after[256];
    tp_error err = {{0}};
    tp_bookmarks b = {0};
    tp_bookmark bm = {.name = "new", .geo = 1, .v = {45, 7, 100, 0, -30}};
    ASSERT_TRUE(tp_bookmarks_set(&b, &bm, &err));
    /* a folder where the file goes: the rename fails (for root too), the folder stays */
    snprintf(path, sizeof path, "%s/taken.bookmarks", dir);
    ASSERT_TRUE(mkdir(path, 0700) == 0);
    EXPECT_FALSE(tp_bookmarks_save(path, &b, &err));
    EXPECT_CONTAINS(err.message, path);
    struct stat st;
    EXPECT_TRUE(stat(path, &st) == 0 && S_ISDIR(st.st_mode));
    /* a file where a folder of the path should be */
    snprintf(path, sizeof path, "%s/file", dir);
    write_text(path, "old --camera-geo 45,7,100,0,-30\n");
    read_text(path, before, sizeof before);
    char inner[1100];
    snprintf(inner, sizeof inner, "%s/x.bookmarks", path);
    EXPECT_FALSE(tp_bookmarks_save(inner, &b, &err));
    EXPECT_CONTAINS(err.message, inner);
    read_text(path, after, sizeof after);
    EXPECT_EQ_STR(before, after);
    /* no temporary file left beside */
    DIR* d = opendir(dir);
    int entries = 0;
    for (struct dirent* e; (e = readdir(d)) != NULL;)
        entries += e->d_name[0] != '.';
    closedir(d);
    EXPECT_EQ_INT(entries, 2);
    tp_bookmarks_free(&b);
}

TEST(default_path_is_keyed_by_the_dem_file_name)
{
    char out[512];
    setenv("XDG_CONFIG_HOME", "/cfg", 1);
    ASSERT_TRUE(tp_bookmarks_default_path("/data/dems/hood.tif", out, sizeof out));
    EXPECT_EQ_STR("/cfg/terrapatch/bookmarks/hood.tif.bookmarks", out);
    unsetenv("XDG_CONFIG_HOME");
    setenv("HOME", "/home/u", 1);
    ASSERT_TRUE(tp_bookmarks_default_path("N42E001.hgt", out, sizeof out));
    EXPECT_EQ_STR("/home/u/.config/terrapatch/bookmarks/N42E001.hgt.bookmarks", out);
}

/* `terrapatch view --headless` on Mount Hood with args; stdout in out, stderr in err. */
static int view(const char* const* args, char* out, size_t out_cap, char* err, size_t err_cap)
{
    const char* dir = getenv("TP_SHARED_DATA_DIR");
    static char dem[1024];
    snprintf(dem, sizeof dem, "%s/lf_elev_220_mt_hood_utm.tif", dir ? dir : TP_TEST_DEFAULT_SHARED_DATA_DIR);
    if (access(dem, R_OK) != 0)
        SKIP("%s missing", dem);
    const char* argv[32];
    int n = 0;
    argv[n++] = "--headless";
    argv[n++] = "--size";
    argv[n++] = "320x180";
    for (int i = 0; args[i]; i++)
        argv[n++] = args[i];
    argv[n++] = dem;
    argv[n] = NULL;
    return tp_test_run_terrapatch_out("view", argv, out, out_cap, err, err_cap);
}

TEST(view_saves_and_recalls_a_bookmark_on_a_real_dem)
{
    const char* dir = make_tmp_dir();
    char file[1024], out[4096], err[4096], out2[4096], text[1024];
    snprintf(file, sizeof file, "%s/hood.bookmarks", dir);
    const char* save[] = {"--bookmarks", file, "--camera-geo", "45.37,-121.70,9000,30,-90",
                          "--save-bookmark", "summit from above", "--pick", "160,90", NULL};
    ASSERT_EQ_INT(0, view(save, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(out, "bookmark 'summit from above' saved in");
    read_text(file, text, sizeof text);
    EXPECT_CONTAINS(text, "\nsummit from above --camera-geo 45.370000000,-121.700000000,9000.00,30.00,-90.00\n");
    const char* recall[] = {"--bookmarks", file, "--bookmark", "summit from above", "--pick",
                            "160,90", NULL};
    ASSERT_EQ_INT(0, view(recall, out2, sizeof out2, err, sizeof err));
    /* the same view: the same ground under the same pixel */
    const char* a = strstr(out, "pick 160.0,90.0: E ");
    const char* b = strstr(out2, "pick 160.0,90.0: E ");
    ASSERT_TRUE(a && b);
    EXPECT_EQ_INT(0, strncmp(a, b, strcspn(a, "\n")));
    EXPECT_TRUE(strstr(a, "no ground") == NULL);
}

TEST(view_unknown_bookmark_exits_1_listing_the_known)
{
    const char* dir = make_tmp_dir();
    char file[1024], out[1024], err[4096];
    snprintf(file, sizeof file, "%s/hood.bookmarks", dir);
    write_text(file, "ridge --camera-geo 45.3,-121.7,4000,0,-30\nview 2 --camera-geo 45.4,-121.7,4000,180,-30\n");
    char stats[1024];
    snprintf(stats, sizeof stats, "%s/stats.json", dir);
    const char* args[] = {"--bookmarks", file, "--bookmark", "summit", "--stats-json", stats, NULL};
    EXPECT_EQ_INT(1, view(args, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(err, "no bookmark 'summit' in");
    EXPECT_CONTAINS(err, "(known: 'ridge', 'view 2')");
    /* a corrupted file: named with its line */
    write_text(file, "ridge --camera-geo 45.3,-121.7,4000,0,-30\nsummit --camera-geo 45.3,-121.7\n");
    const char* args2[] = {"--bookmarks", file, "--bookmark", "ridge", "--stats-json", stats, NULL};
    EXPECT_EQ_INT(1, view(args2, out, sizeof out, err, sizeof err));
    char want[1100];
    snprintf(want, sizeof want, "%s:2: --camera-geo: expected five numbers", file);
    EXPECT_CONTAINS(err, want);
    /* a missing file: no bookmarks */
    snprintf(file, sizeof file, "%s/none.bookmarks", dir);
    EXPECT_EQ_INT(1, view(args, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(err, "(known: none)");
    /* --bookmark with --camera: one start view only */
    const char* both[] = {"--bookmark", "ridge", "--camera", "1,2,3,4,5", NULL};
    EXPECT_EQ_INT(2, view(both, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(err, "give one");
}

#define TESTS(X)                                                                                   \
    X(round_trip_keeps_names_with_spaces_and_values)                                               \
    X(hand_written_file_with_comments_blank_lines_and_spaces)                                      \
    X(corrupted_line_names_file_and_line)                                                          \
    X(missing_file_is_no_bookmarks_and_unreadable_is_an_error)                                     \
    X(names_that_would_not_read_back_are_refused)                                                  \
    X(failed_save_names_the_file_and_leaves_what_was_there)                                        \
    X(default_path_is_keyed_by_the_dem_file_name)                                                \
    X(view_saves_and_recalls_a_bookmark_on_a_real_dem)                                             \
    X(view_unknown_bookmark_exits_1_listing_the_known)
TP_TEST_MAIN(TESTS)
