/* test_fuzz_corpus.c — the fuzz harnesses (tests/fuzz/) replayed over their seed corpus
 * (tests/fuzz/make_corpus.sh), built with the ordinary compiler: every seed goes through the OBJ
 * harness and, behind four option bytes, through the whole-pipeline harness, whose invariants
 * (clean failures, nothing non-finite on success) become CHECKs here.  `make fuzz-check` runs the
 * same harnesses under libFuzzer with ASan/UBSan for a bounded time. */
#define _GNU_SOURCE
#include <dirent.h>
#include <sys/stat.h>

#include "check.h"

void fz_fail(const char *file, int line, const char *what, const char *detail);
static const char *current;

void fz_fail(const char *file, int line, const char *what, const char *detail)
{
    CHECK(0, "%s: invariant %s (%s:%d): %s", current, what, file, line, detail ? detail : "");
}

#include "fuzz/fuzz_model.c"
#include "fuzz/fuzz_obj.c"

static int replay(const char *dir, int (*harness)(const uint8_t *, size_t))
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    char path[1024];
    while (d && (e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        FILE *f = fopen(path, "rb");
        if (!f) continue;
        static uint8_t buf[1 << 16];
        size_t len = fread(buf, 1, sizeof buf, f);
        fclose(f);
        current = path;
        int before = chk_failed;
        harness(buf, len);
        CHECK(chk_failed == before, "%s: invariant violated", path);
        n++;
    }
    if (d) closedir(d);
    return n;
}

int main(void)
{
    char dir[1100], cmd[2600];
    snprintf(dir, sizeof dir, "%s", chk_scratch("fuzz_seeds_XXXXXX"));
    if (!mkdtemp(dir)) { CHECK(0, "mkdtemp"); CHECK_DONE("test_fuzz_corpus"); }
    snprintf(cmd, sizeof cmd, "sh tests/fuzz/make_corpus.sh %s/obj %s/model", dir, dir);
    CHECK(system(cmd) == 0, "make_corpus.sh failed");
    snprintf(cmd, sizeof cmd, "%s/obj", dir);
    int nobj = replay(cmd, q2n_fuzz_obj);
    snprintf(cmd, sizeof cmd, "%s/model", dir);
    int nmodel = replay(cmd, q2n_fuzz_model);
    CHECK(nobj >= 25 && nmodel == 4 * nobj, "seeds: %d OBJ, %d model", nobj, nmodel);
    printf("replayed %d OBJ seeds and %d model seeds\n", nobj, nmodel);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd)) {}
    CHECK_DONE("test_fuzz_corpus");
}
