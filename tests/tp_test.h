/*
 * tp_test.h - the tiny test harness of terrapatch.
 *
 * A test file defines its tests with TEST(name) { ... } and ends with the list of them:
 *
 *     TEST(index_count_matches_formula) { ASSERT_EQ_INT(6, tp_strip_index_count(0)); }
 *     TEST(u16_rejects_level_8) { ... }
 *
 *     #define TESTS(X) X(index_count_matches_formula) X(u16_rejects_level_8)
 *     TP_TEST_MAIN(TESTS)
 *
 * A TEST missing from the list is an unused static function (an error under -Werror), and a
 * listed name without a TEST does not compile, so the list cannot drift from the file.
 * tests/CMakeLists.txt registers every TEST(name) line as its own ctest test "<file>.<name>".
 *
 * The program runs the test named by argv[1], or every test without an argument ("--list"
 * prints the names). Exit status: 0 passed, 1 failed, 77 skipped (SKIP(), e.g. data missing).
 *
 * ASSERT_* stop the test at the first failure (longjmp back to the runner; a failing test may
 * leak what it allocated), EXPECT_* record the failure and go on. Every failure prints
 * file:line and the values compared.
 */
#ifndef TP_TEST_H
#define TP_TEST_H

#undef NDEBUG /* assert() stays on in tests, whatever the build type */
#include <assert.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tp_core.h"

/* ---------------------------------------------------------------------------------------------
 * Registration and runner
 */
typedef struct tp_test_case {
    const char* name;
    void (*fn)(void);
} tp_test_case;

#define TEST(name) static void test_##name(void)
#define TP_TEST_CASE_(name) {#name, test_##name},
#define TP_TEST_MAIN(LIST)                                                                         \
    static const tp_test_case tp_test_cases_[] = {LIST(TP_TEST_CASE_)};                            \
    int main(int argc, char** argv)                                                                \
    {                                                                                              \
        return tp_test_run_(tp_test_cases_, sizeof tp_test_cases_ / sizeof tp_test_cases_[0],      \
                            argc, argv);                                                           \
    }

enum { TP_TEST_PASS_ = 0, TP_TEST_FAIL_ = 1, TP_TEST_SKIP_ = 77 };
#define TP_TEST_MAX_REPORTS_ 25 /* failures printed per test; the rest are only counted */

static struct {
    jmp_buf jump;
    const char* current;
    long failures; /* of the current test */
} tp_test_state_;

static inline void tp_test_report_(const char* file, int line, const char* fmt, ...)
{
    va_list ap;
    tp_test_state_.failures++;
    if (tp_test_state_.failures > TP_TEST_MAX_REPORTS_)
        return;
    fprintf(stderr, "%s:%d: FAIL [%s] ", file, line, tp_test_state_.current);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    if (tp_test_state_.failures == TP_TEST_MAX_REPORTS_)
        fprintf(stderr, "  (further failures of this test are counted, not printed)\n");
}

/* Prints a note under the test's name (values worth seeing in the log, e.g. bytes per sample). */
static inline void tp_test_note(const char* fmt, ...)
{
    va_list ap;
    fprintf(stdout, "  [%s] ", tp_test_state_.current);
    va_start(ap, fmt);
    vfprintf(stdout, fmt, ap);
    va_end(ap);
    fputc('\n', stdout);
    fflush(stdout);
}

static inline int tp_test_run_one_(const tp_test_case* c)
{
    volatile int outcome;
    clock_t start = clock();
    tp_test_state_.current = c->name;
    tp_test_state_.failures = 0;
    fprintf(stdout, "[ RUN      ] %s\n", c->name);
    fflush(stdout);
    outcome = setjmp(tp_test_state_.jump);
    if (outcome == 0) {
        c->fn();
        outcome = tp_test_state_.failures ? TP_TEST_FAIL_ : TP_TEST_PASS_;
    } else if (outcome != TP_TEST_SKIP_) {
        outcome = TP_TEST_FAIL_;
    }
    fflush(stderr);
    fprintf(stdout, "[ %8s ] %s (%.0f ms%s)\n",
            outcome == TP_TEST_PASS_   ? "OK"
            : outcome == TP_TEST_SKIP_ ? "SKIPPED"
                                       : "FAILED",
            c->name, 1000.0 * (double)(clock() - start) / CLOCKS_PER_SEC,
            tp_test_state_.failures > 1 ? ", several failures" : "");
    fflush(stdout);
    return outcome;
}

static inline int tp_test_run_(const tp_test_case* cases, size_t count, int argc, char** argv)
{
    size_t i;
    if (argc > 1 && strcmp(argv[1], "--list") == 0) {
        for (i = 0; i < count; ++i)
            printf("%s\n", cases[i].name);
        return 0;
    }
    if (argc > 1) {
        for (i = 0; i < count; ++i)
            if (strcmp(argv[1], cases[i].name) == 0)
                return tp_test_run_one_(&cases[i]);
        fprintf(stderr, "no test named '%s' in %s (try --list)\n", argv[1], argv[0]);
        return TP_TEST_FAIL_;
    }
    {
        int failed = 0, skipped = 0;
        for (i = 0; i < count; ++i) {
            int r = tp_test_run_one_(&cases[i]);
            failed += r == TP_TEST_FAIL_;
            skipped += r == TP_TEST_SKIP_;
        }
        printf("%d passed, %d failed, %d skipped\n", (int)count - failed - skipped, failed,
               skipped);
        return failed ? TP_TEST_FAIL_ : TP_TEST_PASS_;
    }
}

/* ---------------------------------------------------------------------------------------------
 * Assertions. Arguments are evaluated once. ASSERT_* end the test, EXPECT_* continue.
 */
#define TP_CHECK_(fatal, ok, ...)                                                                  \
    do {                                                                                           \
        if (!(ok)) {                                                                               \
            tp_test_report_(__FILE__, __LINE__, __VA_ARGS__);                                      \
            if (fatal)                                                                             \
                longjmp(tp_test_state_.jump, TP_TEST_FAIL_);                                       \
        }                                                                                          \
    } while (0)

#define TP_TRUE_(fatal, c) TP_CHECK_(fatal, (c), "expected true: %s", #c)

#define TP_EQ_INT_(fatal, a, b)                                                                    \
    do {                                                                                           \
        long long tp_a_ = (long long)(a), tp_b_ = (long long)(b);                                  \
        TP_CHECK_(fatal, tp_a_ == tp_b_, "%s == %s: %lld != %lld", #a, #b, tp_a_, tp_b_);          \
    } while (0)

#define TP_CMP_INT_(fatal, a, op, b)                                                               \
    do {                                                                                           \
        long long tp_a_ = (long long)(a), tp_b_ = (long long)(b);                                  \
        TP_CHECK_(fatal, tp_a_ op tp_b_, "%s %s %s: %lld vs %lld", #a, #op, #b, tp_a_, tp_b_);     \
    } while (0)

#define TP_NEAR_(fatal, a, b, tol)                                                                 \
    do {                                                                                           \
        double tp_a_ = (double)(a), tp_b_ = (double)(b), tp_t_ = (double)(tol);                    \
        TP_CHECK_(fatal, fabs(tp_a_ - tp_b_) <= tp_t_,                                             \
                  "%s ~ %s: %.17g vs %.17g (diff %.3g > %.3g)", #a, #b, tp_a_, tp_b_,              \
                  fabs(tp_a_ - tp_b_), tp_t_);                                                     \
    } while (0)

/* Ordered comparison of doubles; NaN fails. */
#define TP_CMP_DBL_(fatal, a, op, b)                                                               \
    do {                                                                                           \
        double tp_a_ = (double)(a), tp_b_ = (double)(b);                                           \
        TP_CHECK_(fatal, tp_a_ op tp_b_, "%s %s %s: %.17g vs %.17g", #a, #op, #b, tp_a_, tp_b_);   \
    } while (0)

#define TP_NAN_(fatal, a)                                                                          \
    do {                                                                                           \
        double tp_a_ = (double)(a);                                                                \
        TP_CHECK_(fatal, isnan(tp_a_), "%s: expected NaN, got %.17g", #a, tp_a_);                  \
    } while (0)

#define TP_STATUS_(fatal, expected, got)                                                           \
    do {                                                                                           \
        tp_status tp_e_ = (expected), tp_g_ = (got);                                               \
        TP_CHECK_(fatal, tp_e_ == tp_g_, "%s: expected status %d (%s), got %d (%s)", #got,         \
                  (int)tp_e_, tp_test_status_name_(tp_e_), (int)tp_g_,                             \
                  tp_test_status_name_(tp_g_));                                                    \
    } while (0)

#define TP_CONTAINS_(fatal, hay, needle)                                                           \
    do {                                                                                           \
        const char *tp_h_ = (hay), *tp_n_ = (needle);                                              \
        TP_CHECK_(fatal, tp_h_&& tp_n_&& strstr(tp_h_, tp_n_) != NULL,                             \
                  "%s contains %s: \"%s\" does not contain \"%s\"", #hay, #needle,                 \
                  tp_h_ ? tp_h_ : "(null)", tp_n_ ? tp_n_ : "(null)");                             \
    } while (0)

/* Own names, so that a broken tp_status_str cannot break the failure messages. */
static inline const char* tp_test_status_name_(tp_status s)
{
    switch (s) {
    case TP_OK: return "TP_OK";
    case TP_ERR_INVALID_ARG: return "TP_ERR_INVALID_ARG";
    case TP_ERR_BAD_DATA: return "TP_ERR_BAD_DATA";
    case TP_ERR_IO: return "TP_ERR_IO";
    case TP_ERR_OUT_OF_MEMORY: return "TP_ERR_OUT_OF_MEMORY";
    case TP_ERR_BACKEND: return "TP_ERR_BACKEND";
    }
    return "(not a tp_status)";
}

#define ASSERT_TRUE(c) TP_TRUE_(1, c)
#define EXPECT_TRUE(c) TP_TRUE_(0, c)
#define ASSERT_FALSE(c) TP_TRUE_(1, !(c))
#define EXPECT_FALSE(c) TP_TRUE_(0, !(c))
#define ASSERT_EQ_INT(a, b) TP_EQ_INT_(1, a, b)
#define EXPECT_EQ_INT(a, b) TP_EQ_INT_(0, a, b)
#define ASSERT_LE_INT(a, b) TP_CMP_INT_(1, a, <=, b)
#define EXPECT_LE_INT(a, b) TP_CMP_INT_(0, a, <=, b)
#define ASSERT_GE_INT(a, b) TP_CMP_INT_(1, a, >=, b)
#define EXPECT_GE_INT(a, b) TP_CMP_INT_(0, a, >=, b)
#define ASSERT_NEAR(a, b, tol) TP_NEAR_(1, a, b, tol)
#define EXPECT_NEAR(a, b, tol) TP_NEAR_(0, a, b, tol)
#define ASSERT_EQ_DBL(a, b) TP_CMP_DBL_(1, a, ==, b)
#define EXPECT_EQ_DBL(a, b) TP_CMP_DBL_(0, a, ==, b)
#define ASSERT_LE(a, b) TP_CMP_DBL_(1, a, <=, b)
#define EXPECT_LE(a, b) TP_CMP_DBL_(0, a, <=, b)
#define ASSERT_LT(a, b) TP_CMP_DBL_(1, a, <, b)
#define EXPECT_LT(a, b) TP_CMP_DBL_(0, a, <, b)
#define ASSERT_GE(a, b) TP_CMP_DBL_(1, a, >=, b)
#define EXPECT_GE(a, b) TP_CMP_DBL_(0, a, >=, b)
#define ASSERT_GT(a, b) TP_CMP_DBL_(1, a, >, b)
#define EXPECT_GT(a, b) TP_CMP_DBL_(0, a, >, b)
#define ASSERT_NAN(a) TP_NAN_(1, a)
#define EXPECT_NAN(a) TP_NAN_(0, a)
#define ASSERT_STATUS(expected, got) TP_STATUS_(1, expected, got)
#define EXPECT_STATUS(expected, got) TP_STATUS_(0, expected, got)
#define ASSERT_OK(got) TP_STATUS_(1, TP_OK, got)
#define EXPECT_OK(got) TP_STATUS_(0, TP_OK, got)
#define ASSERT_CONTAINS(hay, needle) TP_CONTAINS_(1, hay, needle)
#define EXPECT_CONTAINS(hay, needle) TP_CONTAINS_(0, hay, needle)
#define EXPECT_EQ_STR(expected, got)                                                               \
    do {                                                                                           \
        const char *tp_e_ = (expected), *tp_g_ = (got);                                            \
        TP_CHECK_(0, tp_e_&& tp_g_&& strcmp(tp_e_, tp_g_) == 0, "%s == %s: \"%s\" vs \"%s\"",      \
                  #expected, #got, tp_e_ ? tp_e_ : "(null)", tp_g_ ? tp_g_ : "(null)");            \
    } while (0)
/* A failure with a message of one's own: FAIL("patch %d: ...", p) ends the test. */
#define FAIL(...) TP_CHECK_(1, 0, __VA_ARGS__)
#define ADD_FAILURE(...) TP_CHECK_(0, 0, __VA_ARGS__)
/* Stops the test as skipped (exit status 77): for data or backends that are not there. */
#define SKIP(...)                                                                                  \
    do {                                                                                           \
        fprintf(stdout, "  [%s] skipped: ", tp_test_state_.current);                               \
        fprintf(stdout, __VA_ARGS__);                                                              \
        fputc('\n', stdout);                                                                       \
        longjmp(tp_test_state_.jump, TP_TEST_SKIP_);                                               \
    } while (0)
/* Ends the test early if it has already failed (e.g. before a loop that would repeat it). */
#define ASSERT_NO_FAILURE()                                                                        \
    do {                                                                                           \
        if (tp_test_state_.failures)                                                               \
            longjmp(tp_test_state_.jump, TP_TEST_FAIL_);                                           \
    } while (0)

/* ---------------------------------------------------------------------------------------------
 * Seeded pseudo-random numbers: splitmix64 (Steele, Lea, Flood 2014), so every run is the same.
 */
typedef struct tp_rng {
    uint64_t state;
} tp_rng;

static inline tp_rng tp_rng_seed(uint64_t seed)
{
    tp_rng r;
    r.state = seed;
    return r;
}
static inline uint64_t tp_rng_u64(tp_rng* r)
{
    uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
/* Uniform in [0, 1). */
static inline double tp_rng_unit(tp_rng* r)
{
    return (double)(tp_rng_u64(r) >> 11) * 0x1.0p-53;
}
/* Uniform in [lo, hi). */
static inline double tp_rng_range(tp_rng* r, double lo, double hi)
{
    return lo + (hi - lo) * tp_rng_unit(r);
}
/* Uniform integer in [lo, hi], inclusive. */
static inline int tp_rng_int(tp_rng* r, int lo, int hi)
{
    return lo + (int)(tp_rng_u64(r) % (uint64_t)(hi - lo + 1));
}

/* ---------------------------------------------------------------------------------------------
 * Data files. The directories come from the environment (set by ctest), else from the paths
 * compiled in by tests/CMakeLists.txt, so a test binary also runs by hand.
 */
#ifndef TP_TEST_DEFAULT_SHARED_DATA_DIR
#define TP_TEST_DEFAULT_SHARED_DATA_DIR ""
#endif
#ifndef TP_TEST_DEFAULT_SAMPLE_DATA_DIR
#define TP_TEST_DEFAULT_SAMPLE_DATA_DIR ""
#endif

/* Writes dir/file of the directory named by env_var ("TP_SHARED_DATA_DIR" or
 * "TP_SAMPLE_DATA_DIR") into buf. Returns 1 if that file can be opened for reading. */
static inline int tp_test_data_path(char* buf, size_t cap, const char* env_var, const char* file)
{
    const char* dir = getenv(env_var);
    FILE* f;
    if (!dir || !*dir)
        dir = strcmp(env_var, "TP_SHARED_DATA_DIR") == 0 ? TP_TEST_DEFAULT_SHARED_DATA_DIR
                                                         : TP_TEST_DEFAULT_SAMPLE_DATA_DIR;
    if (!dir || !*dir)
        dir = ".";
    if ((size_t)snprintf(buf, cap, "%s/%s", dir, file) >= cap)
        return 0;
    f = fopen(buf, "rb");
    if (!f)
        return 0;
    fclose(f);
    return 1;
}

/* Fills buf with the path of a data file, or skips the test if it is missing. */
#define REQUIRE_DATA_FILE(buf, env_var, file)                                                      \
    do {                                                                                           \
        if (!tp_test_data_path(buf, sizeof(buf), env_var, file))                                   \
            SKIP("data file %s not found (set %s)", buf, env_var);                                 \
    } while (0)

#endif /* TP_TEST_H */
