/*
 * test_options.c - the one command-line parser (app/base/options.c): the forms of an option and
 * its value, operands among options (and kept in a row), shortened names, negative numbers as
 * operands, the tables' slots and handlers (a name an earlier table has shadowed), and each usage
 * error's line and exit code.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"

#include "cli.h"
#include "options.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* stderr (and stdout) of the code between capture_start and capture_end, into a buffer */
static int saved_fd[2] = {-1, -1};
static FILE* captured[2];

static void capture_start(void)
{
    for (int k = 0; k < 2; ++k) {
        fflush(k ? stderr : stdout);
        captured[k] = tmpfile();
        ASSERT_TRUE(captured[k] != NULL);
        saved_fd[k] = dup(k ? 2 : 1);
        dup2(fileno(captured[k]), k ? 2 : 1);
    }
}

/* What went to stdout (k 0) or stderr (k 1), into out. */
static void capture_end(char out[2][1024])
{
    for (int k = 0; k < 2; ++k) {
        fflush(k ? stderr : stdout);
        dup2(saved_fd[k], k ? 2 : 1);
        close(saved_fd[k]);
        rewind(captured[k]);
        size_t n = fread(out[k], 1, 1023, captured[k]);
        out[k][n] = '\0';
        fclose(captured[k]);
    }
}

enum { CODE_MODE = 300, CODE_LEVEL, CODE_QUIET_X };

typedef struct parsed {
    const char* out;
    const char* from;
    double radius, from_height, step;
    int level, quiet;
    const char* operands[8];
    int operand_count;
    int codes[8], code_count;
    const char* code_values[8];
    int handled[8], handled_count; /* the group's codes its handler saw */
    int exit;                      /* -1: parsed to the end */
    char out_text[1024], err_text[1024];
} parsed;

static int help_called;
static void print_help(void)
{
    ++help_called;
    fputs("usage: terrapatch test [options]\n", stdout);
}

/* A group of options shared by commands: reads --level into the int at ctx. */
static int group_handler(void* ctx, int code, const char* value, const char* cmd)
{
    parsed* r = ctx;
    r->handled[r->handled_count++] = code;
    if (code == CODE_LEVEL && strcmp(value, "high") && strcmp(value, "low"))
        return tp_option_error(cmd, "--level", "high or low", value);
    r->level = !strcmp(value, "high") ? 2 : !strcmp(value, "low") ? 1 : r->level;
    return 1;
}

/* Parses args (NULL-terminated, the command name first) into r. */
static void parse(const char* const* args, int negative_operands, parsed* r)
{
    memset(r, 0, sizeof *r);
    r->radius = -7.0;
    char* argv[32];
    int argc = 0;
    while (args[argc]) {
        argv[argc] = (char*)args[argc];
        ++argc;
    }
    argv[argc] = NULL;
    const tp_option own[] = {
        TP_OPT_TEXT("--output", "-o", &r->out),
        TP_OPT_TEXT("--from", NULL, &r->from),
        TP_OPT_NUMBER("--from-height", &r->from_height, 0.0, 1e6, "a number >= 0"),
        TP_OPT_NUMBER("--radius", &r->radius, 0.0, 1e9, "a number >= 0"),
        TP_OPT_NUMBER_ABOVE("--step", &r->step, 0.0, 1e9, "a number > 0"),
        TP_OPT_FLAG("--quiet", &r->quiet),
        TP_OPT_CODE("--mode", NULL, CODE_MODE, 1),
        TP_OPT_CODE("--size", NULL, CODE_QUIET_X, 0),
    };
    const tp_option group[] = {TP_OPT_CODE("--level", NULL, CODE_LEVEL, 1)};
    tp_options p;
    tp_options_init(&p, "test", argc, argv, print_help);
    p.negative_operands = negative_operands;
    tp_options_add(&p, own, TP_OPTIONS_COUNT(own), NULL, NULL);
    tp_options_add(&p, group, TP_OPTIONS_COUNT(group), group_handler, r);
    capture_start();
    r->exit = -1;
    for (int c; r->exit < 0 && (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_EXIT) {
            r->exit = p.exit;
        } else if (c == TP_OPTIONS_OPERAND) {
            if (r->operand_count == 2)
                r->exit = (tp_options_stray(&p, NULL, ""), p.exit);
            else
                r->operands[r->operand_count++] = p.value;
        } else {
            r->code_values[r->code_count] = p.value;
            r->codes[r->code_count++] = c;
        }
    }
    char text[2][1024];
    capture_end(text);
    memcpy(r->out_text, text[0], sizeof text[0]);
    memcpy(r->err_text, text[1], sizeof text[1]);
}

TEST(long_short_attached_and_shortened_forms_read_the_same)
{
    parsed r;
    const char* a1[] = {"test", "--output", "a.tif", "--radius", "500", NULL};
    parse(a1, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    EXPECT_TRUE(r.out && !strcmp(r.out, "a.tif"));
    EXPECT_EQ_DBL(500.0, r.radius);
    const char* a2[] = {"test", "--output=b.tif", "--radius=1.5", NULL};
    parse(a2, 0, &r);
    EXPECT_TRUE(r.out && !strcmp(r.out, "b.tif"));
    EXPECT_EQ_DBL(1.5, r.radius);
    const char* a3[] = {"test", "-o", "c.tif", "--rad", "2", NULL};
    parse(a3, 0, &r);
    EXPECT_TRUE(r.out && !strcmp(r.out, "c.tif"));
    EXPECT_EQ_DBL(2.0, r.radius);
    const char* a4[] = {"test", "-od.tif", "--ra=3", "--qu", NULL};
    parse(a4, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    EXPECT_TRUE(r.out && !strcmp(r.out, "d.tif"));
    EXPECT_EQ_DBL(3.0, r.radius);
    EXPECT_EQ_INT(1, r.quiet);
    EXPECT_EQ_INT(0, (int)strlen(r.err_text));
}

TEST(an_exact_name_wins_over_a_longer_one_it_begins)
{
    parsed r;
    const char* a[] = {"test", "--from", "45,7", "--from-height", "2", NULL};
    parse(a, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    EXPECT_TRUE(r.from && !strcmp(r.from, "45,7"));
    EXPECT_EQ_DBL(2.0, r.from_height);
    const char* b[] = {"test", "--from-h", "3", NULL};
    parse(b, 0, &r);
    EXPECT_EQ_DBL(3.0, r.from_height);
}

TEST(operands_anywhere_and_after_double_dash)
{
    parsed r;
    const char* a[] = {"test", "dem.tif", "--quiet", "-", NULL};
    parse(a, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    ASSERT_EQ_INT(2, r.operand_count);
    EXPECT_TRUE(!strcmp(r.operands[0], "dem.tif") && !strcmp(r.operands[1], "-"));
    EXPECT_EQ_INT(1, r.quiet);
    /* after "--" an argument starting with '-' is an operand */
    const char* b[] = {"test", "--", "--quiet", NULL};
    parse(b, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    ASSERT_EQ_INT(1, r.operand_count);
    EXPECT_TRUE(!strcmp(r.operands[0], "--quiet"));
    EXPECT_EQ_INT(0, r.quiet);
    /* a third operand: the caller's stray error */
    const char* c[] = {"test", "a", "b", "c", NULL};
    parse(c, 0, &r);
    EXPECT_EQ_INT(TP_EXIT_USAGE, r.exit);
    EXPECT_CONTAINS(r.err_text, "terrapatch: more than one DEM given (see 'terrapatch test --help')");
}

TEST(negative_numbers_are_operands_only_where_the_command_says)
{
    parsed r;
    const char* a[] = {"test", "45.37", "-121.69", NULL};
    parse(a, 1, &r);
    EXPECT_EQ_INT(-1, r.exit);
    ASSERT_EQ_INT(2, r.operand_count);
    EXPECT_TRUE(!strcmp(r.operands[1], "-121.69"));
    parse(a, 0, &r);
    EXPECT_EQ_INT(TP_EXIT_USAGE, r.exit);
    EXPECT_CONTAINS(r.err_text, "unknown option '-121.69'");
    /* an option's value may start with '-' either way */
    const char* b[] = {"test", "--from", "-2.1,40", "--mode", "-x", NULL};
    parse(b, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    EXPECT_TRUE(r.from && !strcmp(r.from, "-2.1,40"));
    ASSERT_EQ_INT(1, r.code_count);
    EXPECT_EQ_INT(CODE_MODE, r.codes[0]);
    EXPECT_TRUE(!strcmp(r.code_values[0], "-x"));
}

TEST(codes_go_to_the_caller_and_groups_to_their_handler)
{
    parsed r;
    const char* a[] = {"test", "--size", "--level", "high", "--mode=fast", NULL};
    parse(a, 0, &r);
    EXPECT_EQ_INT(-1, r.exit);
    ASSERT_EQ_INT(2, r.code_count);
    EXPECT_EQ_INT(CODE_QUIET_X, r.codes[0]);
    EXPECT_TRUE(r.code_values[0] == NULL);
    EXPECT_EQ_INT(CODE_MODE, r.codes[1]);
    EXPECT_TRUE(!strcmp(r.code_values[1], "fast"));
    ASSERT_EQ_INT(1, r.handled_count);
    EXPECT_EQ_INT(CODE_LEVEL, r.handled[0]);
    EXPECT_EQ_INT(2, r.level);
    /* the handler's refusal ends the parse with exit 2 and its own line */
    const char* b[] = {"test", "--level", "medium", "--quiet", NULL};
    parse(b, 0, &r);
    EXPECT_EQ_INT(TP_EXIT_USAGE, r.exit);
    EXPECT_CONTAINS(r.err_text, "--level: expected high or low, got 'medium'");
    EXPECT_EQ_INT(0, r.quiet);
}

TEST(each_usage_error_is_one_line_and_exit_2)
{
    static const struct {
        const char* args[5];
        const char* line;
    } cases[] = {
        {{"--bogus"}, "terrapatch: unknown option '--bogus' (see 'terrapatch test --help')\n"},
        {{"-x"}, "terrapatch: unknown option '-x' (see"},
        {{"--radius"}, "terrapatch: missing value for --radius (see"},
        {{"--quiet=1"}, "terrapatch: --quiet takes no value (see"},
        {{"--radius", "-1"}, "terrapatch: --radius: expected a number >= 0, got '-1'\n"},
        {{"--radius", "nan"}, "--radius: expected a number >= 0, got 'nan'"},
        {{"--radius", "1e99999"}, "--radius: expected a number >= 0, got '1e99999'"},
        {{"--step", "0"}, "--step: expected a number > 0, got '0'"},
        {{"--from", "45,7", "--to"}, "unknown option '--to'"},
        {{"--from", "42.5", "-2.1"},
         "unknown option '-2.1' (quote a position with spaces: --from \"42.5 -2.1\")"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        const char* args[7] = {"test"};
        for (int j = 0; j < 5 && cases[k].args[j]; ++j)
            args[j + 1] = cases[k].args[j];
        parsed r;
        parse(args, 0, &r);
        tp_test_note("%s -> %s", cases[k].args[0], r.err_text);
        EXPECT_EQ_INT(TP_EXIT_USAGE, r.exit);
        EXPECT_CONTAINS(r.err_text, cases[k].line);
        EXPECT_TRUE(strchr(r.err_text, '\n') == r.err_text + strlen(r.err_text) - 1);
    }
}

TEST(a_shortened_name_that_fits_several_is_refused_naming_them)
{
    parsed r;
    const char* a[] = {"test", "--fr", "1", NULL};
    parse(a, 0, &r);
    EXPECT_EQ_INT(TP_EXIT_USAGE, r.exit);
    EXPECT_CONTAINS(r.err_text, "option '--fr' is ambiguous: --from, --from-height");
    EXPECT_TRUE(r.from == NULL);
}

TEST(help_prints_and_ends_with_exit_0)
{
    parsed r;
    help_called = 0;
    const char* a[] = {"test", "--radius", "5", "--help", "--bogus", NULL};
    parse(a, 0, &r);
    EXPECT_EQ_INT(TP_EXIT_OK, r.exit);
    EXPECT_EQ_INT(1, help_called);
    EXPECT_CONTAINS(r.out_text, "usage: terrapatch test");
    EXPECT_EQ_INT(0, (int)strlen(r.err_text));
    const char* b[] = {"test", "-h", NULL};
    parse(b, 0, &r);
    EXPECT_EQ_INT(TP_EXIT_OK, r.exit);
    EXPECT_EQ_INT(2, help_called);
}

TEST(integer_values_refuse_fractions_and_trailing_text)
{
    long v = -1;
    capture_start();
    int ok1 = tp_option_integer("test", "--n", "12", 0, 20, "0 .. 20", &v);
    int ok2 = tp_option_integer("test", "--n", "3.5", 0, 20, "0 .. 20", &v);
    int ok3 = tp_option_integer("test", "--n", "21", 0, 20, "0 .. 20", &v);
    int ok4 = tp_option_integer("test", "--n", "", 0, 20, "0 .. 20", &v);
    int ok5 = tp_option_integer("test", "--n", NULL, 0, 20, "0 .. 20", &v);
    char text[2][1024];
    capture_end(text);
    EXPECT_EQ_INT(1, ok1);
    EXPECT_EQ_INT(12, (int)v);
    EXPECT_EQ_INT(0, ok2 + ok3 + ok4 + ok5);
    EXPECT_CONTAINS(text[1], "--n: expected 0 .. 20, got '3.5'");
    EXPECT_CONTAINS(text[1], "--n: expected 0 .. 20, got '21'");
    EXPECT_CONTAINS(text[1], "--n: expected 0 .. 20, got ''");
}

/* A group's handler that must not be called. */
static int shadowed_handler(void* ctx, int code, const char* value, const char* cmd)
{
    (void)code, (void)value, (void)cmd;
    ++*(int*)ctx;
    return 1;
}

TEST(kept_operands_end_up_in_a_row_and_an_earlier_table_shadows_a_name)
{
    char* argv[] = {(char*)"test", (char*)"a",      (char*)"--quiet", (char*)"b",
                    (char*)"--origin", (char*)"x", (char*)"c",       (char*)"--ori",
                    (char*)"y",    NULL};
    const int argc = 9;
    int quiet = 0, shadowed = 0, kept = 0, codes = 0;
    const tp_option own[] = {TP_OPT_FLAG("--quiet", &quiet), TP_OPT_CODE("--origin", NULL, 1, 1)};
    const tp_option group[] = {TP_OPT_CODE("--origin", NULL, 2, 1)};
    tp_options p;
    tp_options_init(&p, "test", argc, argv, print_help);
    tp_options_add(&p, own, TP_OPTIONS_COUNT(own), NULL, NULL);
    tp_options_add(&p, group, TP_OPTIONS_COUNT(group), shadowed_handler, &shadowed);
    capture_start();
    int c;
    while ((c = tp_options_next(&p)) > 0 || c == TP_OPTIONS_OPERAND) {
        if (c == TP_OPTIONS_OPERAND)
            tp_options_keep(&p, &kept);
        else
            codes += c == 1 && (!strcmp(p.value, "x") || !strcmp(p.value, "y"));
    }
    char text[2][1024];
    capture_end(text);
    EXPECT_EQ_INT(TP_OPTIONS_END, c);
    EXPECT_EQ_INT(0, (int)strlen(text[1]));
    ASSERT_EQ_INT(3, kept);
    EXPECT_TRUE(!strcmp(argv[1], "a") && !strcmp(argv[2], "b") && !strcmp(argv[3], "c"));
    EXPECT_EQ_INT(1, quiet);
    EXPECT_EQ_INT(2, codes);   /* --origin and --ori: the first table's */
    EXPECT_EQ_INT(0, shadowed);
}

#define TESTS(X)                                                                                   \
    X(long_short_attached_and_shortened_forms_read_the_same)                                       \
    X(an_exact_name_wins_over_a_longer_one_it_begins)                                              \
    X(operands_anywhere_and_after_double_dash)                                                     \
    X(negative_numbers_are_operands_only_where_the_command_says)                                   \
    X(codes_go_to_the_caller_and_groups_to_their_handler)                                          \
    X(each_usage_error_is_one_line_and_exit_2)                                                     \
    X(a_shortened_name_that_fits_several_is_refused_naming_them)                                   \
    X(help_prints_and_ends_with_exit_0)                                                            \
    X(integer_values_refuse_fractions_and_trailing_text)                                           \
    X(kept_operands_end_up_in_a_row_and_an_earlier_table_shadows_a_name)
TP_TEST_MAIN(TESTS)
