/* test_layout.c — the source tree's own rules, checked on the tree and on the built library:
 *   - every symbol the library exports starts with q2n_ (nm on build/libquad2nurbs.a; weak C++
 *     template instances of std:: and ceres:: come from the Ceres shim and are not ours);
 *   - headers are clean: nothing but comments after the include guard's #endif, no #include
 *     after the first line of code (in .c files too);
 *   - stages include only earlier stages (folders of src/, in pipeline order), and src/cli/ uses
 *     only the public header include/quad2nurbs.h;
 *   - the face parametrization is declared once (src/patch/surface.h): no copy of its corner or
 *     side tables elsewhere in src/ or tests/ (test_augmented.c writes it out as its reference);
 *   - policy lives in the stages' policy headers (*policy.h): no #define of a floating-point
 *     value in a src/ .c file, and every small literal threshold (1e-N) left in src/ code is on
 *     an explicit list of numerical guards (rounding floors, singularity tests, difference steps);
 *   - no src/ file names a shared test mesh (mesh stories go to docs/ and commit messages).
 * Each rule's checker is also run on a made-up violation, so that the test can fail. */
#include <ctype.h>
#include <dirent.h>
#include <libgen.h>
#include <strings.h>

#include "check.h"

/* ------------------------------------------------------------------ files */

/* Comments replaced by blanks (newlines kept, so line numbers stay), string literals kept. */
static void strip_comments(char *s)
{
    for (char *p = s; *p; p++) {
        if (*p == '"') { /* a string literal: skip it */
            for (p++; *p && *p != '"'; p++)
                if (*p == '\\' && p[1]) p++;
            if (!*p) return;
        } else if (p[0] == '/' && p[1] == '*') {
            char *e = strstr(p + 2, "*/");
            char *end = e ? e + 2 : p + strlen(p);
            for (; p < end; p++)
                if (*p != '\n') *p = ' ';
            p--;
        } else if (p[0] == '/' && p[1] == '/') {
            for (; *p && *p != '\n'; p++) *p = ' ';
            if (!*p) return;
        }
    }
}

typedef void (*file_fn)(const char *path, const char *text, void *arg);

/* fn on every file DIR/SUB/NAME with the given suffixes (SUB: one level of folders, or none). */
static int each_file(const char *dir, const char *const *suffixes, file_fn fn, void *arg)
{
    DIR *d = opendir(dir);
    if (!d) return 0;
    int n = 0;
    struct dirent *e;
    static char names[512][256];
    int nn = 0;
    while ((e = readdir(d)) && nn < 512)
        if (e->d_name[0] != '.') snprintf(names[nn++], sizeof names[0], "%.255s", e->d_name);
    closedir(d);
    char (*own)[256] = malloc(sizeof names[0] * (size_t)(nn ? nn : 1)); /* names is reused below */
    if (!own) return 0;
    memcpy(own, names, sizeof names[0] * (size_t)nn);
    for (int i = 0; i < nn; i++) {
        char p[1400];
        snprintf(p, sizeof p, "%.1000s/%.255s", dir, own[i]);
        struct stat st;
        if (stat(p, &st) != 0) continue;
        if (S_ISDIR(st.st_mode)) { n += each_file(p, suffixes, fn, arg); continue; }
        size_t l = strlen(p);
        for (const char *const *s = suffixes; *s; s++)
            if (l > strlen(*s) && !strcmp(p + l - strlen(*s), *s)) {
                char *t = chk_slurp(p, NULL);
                if (t) { fn(p, t, arg); n++; }
                free(t);
                break;
            }
    }
    free(own);
    return n;
}

/* ------------------------------------------------------------------ symbols */

/* 1 when nm's (type, name) is an exported symbol that breaks the prefix rule. */
static int bad_symbol(char type, const char *name)
{
    if (type == 'U' || islower((unsigned char)type)) return 0; /* undefined or local */
    if (!strncmp(name, "__odr_asan", 10) || !strncmp(name, "__asan", 6) || !strncmp(name, "__ubsan", 7))
        return 0;                                              /* sanitizer instrumentation (make CONFIG=asan) */
    if (type == 'W' || type == 'V') {                          /* vague linkage: C++ template instances */
        static const char *const ok[] = {"_ZNSt", "_ZNKSt", "_ZSt", "_ZN5ceres", "_ZNK5ceres", "_ZN9__gnu_cxx",
                                         "_ZN5Eigen", "_ZNK5Eigen", /* Eigen: the matrices of Ceres' TinySolver */
                                         "DW.ref.__gxx_personality_v0",
                                         "_ZTISt", "_ZTSSt", /* typeinfo of std:: classes (emitted at -O1) */
                                         NULL};
        for (const char *const *o = ok; *o; o++)
            if (!strncmp(name, *o, strlen(*o))) return 0;
        return 1;
    }
    return strncmp(name, "q2n_", 4) != 0;
}

static void test_symbols(void)
{
    CHECK(bad_symbol('T', "fit_now") && bad_symbol('D', "rd_tok_table") && !bad_symbol('T', "q2n_now") &&
              !bad_symbol('t', "helper") && !bad_symbol('U', "dgesvd_") && bad_symbol('W', "_Z9my_inlinev") &&
              !bad_symbol('W', "_ZNSt6vectorIdSaIdEE17_M_default_appendEm") &&
              !bad_symbol('W', "_ZN5Eigen8internal19throw_std_bad_allocEv") && bad_symbol('T', "_ZN5Eigen3fooEv") &&
              !bad_symbol('B', "__odr_asan.q2n_binom") && bad_symbol('B', "odr_table"),
          "the symbol rule itself");
    char exe[1024], lib[1100], cmd[1200];
    snprintf(exe, sizeof exe, "%s", chk_exe());
    snprintf(lib, sizeof lib, "%s/libquad2nurbs.a", dirname(exe));
    if (access(lib, R_OK) != 0) { CHECK(0, "library %s not found", lib); return; }
    snprintf(cmd, sizeof cmd, "nm -g --defined-only '%s' 2>&1", lib);
    FILE *p = popen(cmd, "r");
    if (!p) { SKIP("nm cannot be run"); return; }
    char line[4096], obj[256] = "";
    int n = 0, bad = 0;
    while (fgets(line, sizeof line, p)) {
        char a[64], t[8], name[4000];
        size_t l = strlen(line);
        if (l > 2 && line[l - 2] == ':') { snprintf(obj, sizeof obj, "%.*s", (int)(l - 2), line); continue; }
        if (sscanf(line, "%63s %7s %3999s", a, t, name) != 3) continue;
        n++;
        if (bad_symbol(t[0], name)) {
            bad++;
            CHECK(0, "%s exports %s (%c): exported names start with q2n_", obj, name, t[0]);
        }
    }
    int rc = pclose(p);
    CHECK(rc == 0 && n > 100, "nm read %d symbols of %s (exit %d)", n, lib, rc);
    CHECK(bad == 0, "%d symbols without the q2n_ prefix", bad);
}

/* ------------------------------------------------------------------ headers */

typedef struct header_report { int files, bad; char first[1024]; } header_report;

static void report(header_report *r, const char *path, int line, const char *what)
{
    if (!r->bad++) snprintf(r->first, sizeof r->first, "%.300s:%d: %.600s", path, line, what);
}

/* Includes before code, nothing after a header's closing #endif. */
static void check_header_text(const char *path, const char *text, void *arg)
{
    header_report *r = arg;
    char *t = strdup(text);
    strip_comments(t);
    r->files++;
    int code = 0, line = 0, last_endif = 0, after_endif = 0;
    for (char *s = t; *s;) {
        char *e = strchr(s, '\n');
        if (e) *e = 0;
        line++;
        while (isspace((unsigned char)*s)) s++;
        if (*s) {
            if (!strncmp(s, "#include", 8)) {
                if (code) report(r, path, line, "#include after code");
            } else if (*s != '#') code = 1;
            if (!strncmp(s, "#endif", 6)) last_endif = line, after_endif = 0;
            else after_endif = 1;
        }
        if (!e) break;
        s = e + 1;
    }
    size_t l = strlen(path);
    if (l > 2 && !strcmp(path + l - 2, ".h") && (after_endif || !last_endif))
        report(r, path, line, "something after the include guard's #endif");
    free(t);
}

static void test_headers(void)
{
    header_report r = {0};
    check_header_text("a.h", "#ifndef A_H\n#define A_H\nint f(void);\n#endif\nint g(void);\n", &r);
    CHECK(r.bad == 1, "a declaration after #endif is found");
    r.bad = 0;
    check_header_text("b.c", "#include <x.h>\nint f(void);\n#include \"y.h\"\n", &r);
    CHECK(r.bad == 1, "an #include after code is found");
    r.bad = 0;
    check_header_text("c.h", "/* c */\n#ifndef C_H\n#define C_H\n#include <x.h>\n#if 1\nint f(void);\n#endif\n"
                             "#endif\n/* done */\n", &r);
    CHECK(r.bad == 0, "a clean header passes: %s", r.first);
    header_report all = {0};
    static const char *const sfx[] = {".h", ".c", ".cpp", NULL};
    each_file("src", sfx, check_header_text, &all);
    each_file("include", sfx, check_header_text, &all);
    CHECK(all.files > 80, "%d source files read (run from the repository root)", all.files);
    CHECK(all.bad == 0, "%d header-rule violations, the first: %s", all.bad, all.first);
}

/* ------------------------------------------------------------------ stages */

static const char *const STAGES[] = {"core", "mesh", "param", "spline", "patch", "acc", "fit", "iges", "api", "cli", NULL};

static int stage_rank(const char *name, size_t n)
{
    for (int i = 0; STAGES[i]; i++)
        if (strlen(STAGES[i]) == n && !strncmp(STAGES[i], name, n)) return i;
    return -1;
}

/* Stage of a file src/STAGE/NAME (-1 if none). */
static int file_stage(const char *path)
{
    const char *s = strstr(path, "src/");
    if (!s) return -1;
    s += 4;
    const char *e = strchr(s, '/');
    return e ? stage_rank(s, (size_t)(e - s)) : -1;
}

/* Quoted includes of a file: "STAGE/..." of a later stage, and (src/cli/) anything but the
 * public header and the command's own files. */
static void check_includes(const char *path, const char *text, void *arg)
{
    header_report *r = arg;
    int st = file_stage(path), line = 0, cli = stage_rank("cli", 3);
    r->files++;
    for (const char *s = text; *s;) {
        const char *e = strchr(s, '\n');
        size_t n = e ? (size_t)(e - s) : strlen(s);
        line++;
        char buf[512];
        snprintf(buf, sizeof buf, "%.*s", (int)(n < 511 ? n : 511), s);
        const char *q = buf;
        while (isspace((unsigned char)*q)) q++;
        if (!strncmp(q, "#include \"", 10)) {
            const char *inc = q + 10, *slash = strchr(inc, '/'), *close = strchr(inc, '"');
            int ist = slash && close && slash < close ? stage_rank(inc, (size_t)(slash - inc)) : -1;
            char what[400];
            if (ist > st) {
                snprintf(what, sizeof what, "includes %.*s, a later stage", (int)(close ? close - inc : 20), inc);
                report(r, path, line, what);
            }
            if (st == cli && strncmp(inc, "quad2nurbs.h\"", 13) && strncmp(inc, "cli", 3) && ist != cli) {
                snprintf(what, sizeof what, "the command includes %.*s: it uses only include/quad2nurbs.h",
                         (int)(close ? close - inc : 20), inc);
                report(r, path, line, what);
            }
        }
        if (!e) break;
        s = e + 1;
    }
}

static void test_stages(void)
{
    header_report r = {0};
    check_includes("src/mesh/x.c", "#include \"core/error.h\"\n#include \"fit/fit.h\"\n", &r);
    CHECK(r.bad == 1, "a backward include is found");
    r.bad = 0;
    check_includes("src/cli/x.c", "#include \"quad2nurbs.h\"\n#include \"cli.h\"\n#include \"api/model.h\"\n", &r);
    CHECK(r.bad == 1, "the command reaching into the library is found");
    header_report all = {0};
    static const char *const sfx[] = {".h", ".c", ".cpp", NULL};
    each_file("src", sfx, check_includes, &all);
    CHECK(all.bad == 0, "%d include-rule violations, the first: %s", all.bad, all.first);
}

/* ------------------------------------------------------------------ conventions */

/* The face parametrization's tables as they are written out (spacing normalised). */
static const char *const TABLES[] = {"{0,0},{1,0},{1,1},{0,1}", "{1,-1,-1,1}", "{0,1,1,0}",
                                     "{1,0},{0,1},{-1,0},{0,-1}", "{0,1},{-1,0},{0,-1},{1,0}",
                                     "{0,0},{1,0},{0,1},{2,0},{1,1},{0,2}", "{0,1,0,2,1,0}", NULL};
/* Their one home, the test that writes the table out as its reference, and this file. */
static const char *const TABLE_HOMES[] = {"src/patch/surface.c", "tests/test_augmented.c", "tests/test_layout.c", NULL};

static void check_tables(const char *path, const char *text, void *arg)
{
    header_report *r = arg;
    r->files++;
    for (const char *const *h = TABLE_HOMES; *h; h++)
        if (strlen(path) >= strlen(*h) && !strcmp(path + strlen(path) - strlen(*h), *h)) return;
    char *t = strdup(text), *w = t;
    int *lines = malloc(sizeof(int) * (strlen(text) + 1)), line = 1;
    if (!t || !lines) { free(t); free(lines); return; }
    strip_comments(t);
    for (const char *s = t; *s; s++) { /* drop blanks and newlines, remember the lines */
        if (!isspace((unsigned char)*s)) lines[w - t] = line, *w++ = *s;
        line += *s == '\n';
    }
    *w = 0;
    for (const char *const *p = TABLES; *p; p++) {
        const char *hit = strstr(t, *p);
        if (hit) {
            int line = lines[hit - t];
            char what[128];
            snprintf(what, sizeof what, "a copy of the face parametrization's table %s (use patch/surface.h)", *p);
            report(r, path, line, what);
        }
    }
    free(t);
    free(lines);
}

static void test_conventions(void)
{
    header_report r = {0};
    check_tables("src/fit/x.c", "static const int cuv[4][2] = {{0, 0}, {1, 0},\n {1, 1}, {0, 1}};\n", &r);
    CHECK(r.bad == 1, "a copied corner table is found");
    header_report all = {0};
    static const char *const sfx[] = {".h", ".c", ".cpp", NULL};
    each_file("src", sfx, check_tables, &all);
    each_file("tests", sfx, check_tables, &all);
    CHECK(all.bad == 0, "%d copies of convention tables, the first: %s", all.bad, all.first);
}

/* ------------------------------------------------------------------ policy */

/* Small literals (digits, optional fraction, e-N) allowed in src/ code outside the policy headers,
 * by file: numerical guards whose value follows from floating point, not from judgement. */
typedef struct allowed_literal { const char *file, *literals, *why; } allowed_literal;
static const allowed_literal ALLOWED[] = {
    {"src/acc/acc_quality.c", "1e-300", "division floor"},
    {"src/patch/surface.c", "1e-15", "Gauss-Newton step at rounding"},
    {"src/fit/fit_target.c", "1e-30", "CG stops when the residual underflows"},
    {"src/fit/fit_measure.c", "1e-14", "a distance at rounding needs no projection"},
    {"src/patch/ev_derivatives.c", "1e-14", "singular 2x2 test relative to rounding"},
    {"src/patch/curve_network.c", "1e-14 1e-300", "singular 2x2 test; division floor"},
    {"src/patch/ev_harmonize.c", "1e-6 1e-9 1e-300 1e-10", "probe step; Cholesky jitter; division floor"},
    {"src/patch/ev_fair_patch.c", "1e-4 1e-12", "central-difference step; singular 2x2 test"},
    {"src/mesh/fill.c", "1e-12", "singular 2x2 test (two planes parallel to rounding)"},
    {"src/mesh/frame.c", "1e-300 1e-6 1e-20", "Jacobi stops when the off-diagonals underflow; central-difference step; Gauss-Newton step at rounding"},
    {"src/core/poly.c", "1e-15", "Newton's iteration at rounding"},
    {"src/core/clock.c", "1e-9", "nanoseconds"},
    {"src/cli/main.c", "1e-3 1e-6 1e-9", "unit prefixes"},
    {NULL, NULL, NULL}};
/* #define of a floating-point value allowed in a .c file: constants of a formula. */
static const char *const ALLOWED_DEFINES[] = {"FIT_SQRT1_2", NULL};

static int ends_with(const char *s, const char *t) { size_t a = strlen(s), b = strlen(t); return a >= b && !strcmp(s + a - b, t); }

static int literal_allowed(const char *path, const char *lit)
{
    for (const allowed_literal *a = ALLOWED; a->file; a++)
        if (ends_with(path, a->file)) {
            size_t n = strlen(lit);
            for (const char *p = a->literals; (p = strstr(p, lit)); p += n)
                if ((p == a->literals || p[-1] == ' ') && (p[n] == 0 || p[n] == ' ')) return 1;
        }
    return 0;
}

/* Strings blanked (comments already are), so that messages do not count as code. */
static void blank_strings(char *s)
{
    for (char *p = s; *p; p++)
        if (*p == '"' || *p == '\'') {
            char q = *p;
            for (p++; *p && *p != q && *p != '\n'; p++) {
                if (*p == '\\' && p[1]) *p++ = ' ';
                *p = ' ';
            }
            if (!*p) return;
        }
}

static void check_policy(const char *path, const char *text, void *arg)
{
    header_report *r = arg;
    if (!ends_with(path, ".c") && !ends_with(path, ".cpp")) return;
    r->files++;
    char *t = strdup(text);
    if (!t) return;
    strip_comments(t);
    blank_strings(t);
    int line = 1;
    for (char *s = t; *s;) {
        char *e = strchr(s, '\n');
        if (e) *e = 0;
        const char *q = s;
        while (isspace((unsigned char)*q)) q++;
        char what[300];
        if (!strncmp(q, "#define", 7)) { /* #define NAME value: a floating-point value is policy */
            char name[128] = "", val[128] = "";
            if (sscanf(q + 7, " %127[A-Za-z0-9_] %127s", name, val) == 2 && !strchr(name, '(')) {
                const char *v = val;
                while (*v == '(') v++;
                int isnum = isdigit((unsigned char)*v) || (*v == '.' && isdigit((unsigned char)v[1]));
                int isfloat = isnum && strpbrk(v, ".eE") && strncmp(v, "0x", 2);
                int ok = 0;
                for (const char *const *a = ALLOWED_DEFINES; *a; a++) ok |= !strcmp(*a, name);
                if (isfloat && !ok) {
                    snprintf(what, sizeof what, "#define %.100s %.60s: a tuned value belongs in the stage's policy header", name, val);
                    report(r, path, line, what);
                }
            }
        } else
            for (const char *p = q; *p; p++) { /* literals d[.d]e-N not inside a name */
                if (!isdigit((unsigned char)*p) || (p > q && (isalnum((unsigned char)p[-1]) || p[-1] == '_' || p[-1] == '.')))
                    continue;
                const char *b = p;
                while (isdigit((unsigned char)*p) || *p == '.') p++;
                if ((*p == 'e' || *p == 'E') && p[1] == '-' && isdigit((unsigned char)p[2])) {
                    p += 2;
                    while (isdigit((unsigned char)*p)) p++;
                    char lit[64];
                    snprintf(lit, sizeof lit, "%.*s", (int)(p - b < 63 ? p - b : 63), b);
                    if (!literal_allowed(path, lit)) {
                        snprintf(what, sizeof what, "literal threshold %s: move it to the stage's policy header with its why "
                                 "(or list it in test_layout.c's numerical guards)", lit);
                        report(r, path, line, what);
                    }
                }
                if (!*p) break;
            }
        line++;
        if (!e) break;
        s = e + 1;
    }
    free(t);
}

static void test_policy(void)
{
    header_report r = {0};
    check_policy("src/fit/x.c", "#define SPIKE 10.0 /* ratio */\n#define N 4\n#define TWO_PI (2 * Q2N_PI)\n", &r);
    CHECK(r.bad == 1, "a #define of a tuned float is found, integers and expressions pass (%d)", r.bad);
    r.bad = 0;
    check_policy("src/core/clock.c", "double t = 1e-9 * ns; /* 1e-3 */ const char *m = \"1e-7\";\n"
                                      "if (x < 2.5e-8 * d) y = 1e-9;\n", &r);
    CHECK(r.bad == 1 && strstr(r.first, "2.5e-8"), "an unlisted literal threshold is found, listed ones, comments "
          "and strings pass: %d, %s", r.bad, r.first);
    header_report all = {0};
    static const char *const sfx[] = {".c", ".cpp", NULL};
    each_file("src", sfx, check_policy, &all);
    CHECK(all.files > 40, "%d source files read", all.files);
    CHECK(all.bad == 0, "%d policy-rule violations, the first: %s", all.bad, all.first);
}

/* ------------------------------------------------------------------ mesh stories */

/* The shared test meshes by name (../shared/meshes); src/ states reasons generally. */
static const char *const MESH_NAMES[] = {"pawn", "helmet", "crane_spot", "rook", "osd_catmark", "gismo_", "polycube",
                                         "carpet", "gregory_test", "fvar_bound", "bitorus", "righthanded",
                                         "octtorus", "demo_torus", NULL};

static void check_mesh_names(const char *path, const char *text, void *arg)
{
    header_report *r = arg;
    r->files++;
    int line = 1;
    for (const char *s = text; *s; s++) {
        if (*s == '\n') { line++; continue; }
        for (const char *const *n = MESH_NAMES; *n; n++) {
            size_t k = strlen(*n);
            if (!strncasecmp(s, *n, k)) {
                char what[200];
                snprintf(what, sizeof what, "names the test mesh '%s' (state the reason generally; the case goes to docs/)", *n);
                report(r, path, line, what);
            }
        }
    }
}

static void test_mesh_names(void)
{
    header_report r = {0};
    check_mesh_names("src/patch/x.c", "/* the cap keeps\n * osd_catmark_helmet smooth */\nint x;\n", &r);
    CHECK(r.bad >= 1 && strstr(r.first, ":2:"), "a comment naming a shared mesh is found (%s)", r.first);
    header_report all = {0};
    static const char *const sfx[] = {".h", ".c", ".cpp", NULL};
    each_file("src", sfx, check_mesh_names, &all);
    CHECK(all.bad == 0, "%d mentions of shared meshes in src/, the first: %s", all.bad, all.first);
}

int main(void)
{
    test_symbols();
    test_headers();
    test_stages();
    test_conventions();
    test_policy();
    test_mesh_names();
    CHECK_DONE("test_layout");
}
