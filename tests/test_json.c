/*
 * test_json.c - the JSON writer of the --json outputs (app/base/json.c): a document's exact
 * text (commas, indentation, one newline at its end), escaping, NaN as null, and the member
 * helpers writing what a key and a value written apart write.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"

#include "json.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* What write(j) printed, into out. */
static void printed(void (*write)(tp_json* j), char* out, size_t cap)
{
    FILE* f = tmpfile();
    ASSERT_TRUE(f != NULL);
    tp_json j;
    tp_json_init(&j, f);
    write(&j);
    rewind(f);
    size_t n = fread(out, 1, cap - 1, f);
    out[n] = '\0';
    fclose(f);
}

static void apart(tp_json* j)
{
    tp_json_object_begin(j);
    tp_json_key(j, "name");
    tp_json_string(j, "a \"b\"\n\xff");
    tp_json_key(j, "x");
    tp_json_number(j, 0.1);
    tp_json_key(j, "n");
    tp_json_int(j, -3);
    tp_json_key(j, "size");
    tp_json_size(j, 7);
    tp_json_key(j, "ok");
    tp_json_bool(j, 1);
    tp_json_key(j, "void");
    tp_json_number(j, NAN);
    tp_json_key(j, "list");
    tp_json_array_begin(j);
    tp_json_int(j, 1);
    tp_json_int(j, 2);
    tp_json_array_end(j);
    tp_json_object_end(j);
}

static void together(tp_json* j)
{
    tp_json_object_begin(j);
    tp_json_member_string(j, "name", "a \"b\"\n\xff");
    tp_json_member_number(j, "x", 0.1);
    tp_json_member_int(j, "n", -3);
    tp_json_member_size(j, "size", 7);
    tp_json_member_bool(j, "ok", 1);
    tp_json_member_number(j, "void", NAN);
    tp_json_key(j, "list");
    tp_json_array_begin(j);
    tp_json_int(j, 1);
    tp_json_int(j, 2);
    tp_json_array_end(j);
    tp_json_object_end(j);
}

TEST(a_document_reads_as_written_and_ends_with_one_newline)
{
    char a[1024], b[1024];
    printed(apart, a, sizeof a);
    printed(together, b, sizeof b);
    EXPECT_TRUE(!strcmp(a, "{\n"
                           "  \"name\": \"a \\\"b\\\"\\n\\ufffd\",\n"
                           "  \"x\": 0.10000000000000001,\n"
                           "  \"n\": -3,\n"
                           "  \"size\": 7,\n"
                           "  \"ok\": true,\n"
                           "  \"void\": null,\n"
                           "  \"list\": [1, 2]\n"
                           "}\n"));
    tp_test_note("%s", a);
    EXPECT_TRUE(!strcmp(a, b));
}

#define TESTS(X) X(a_document_reads_as_written_and_ends_with_one_newline)
TP_TEST_MAIN(TESTS)
