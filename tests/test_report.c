/* test_report.c — runs tests/test_report.py, the test of the HTML continuity report
 * (tools/q2n_report.py, tools/q2n_render.py, tools/q2n_nurbs.py), with /usr/bin/python3 (Debian's,
 * the one with FreeCAD).  The Python program prints its own FAIL/SKIP lines and the closing
 * "test_report: N passed, N failed, N skipped"; this wrapper exists because tests/run_tests.sh runs the
 * build/tests/test_* executables the Makefile builds from tests/test_*.c. */
#include "check.h"

int main(void)
{
    if (access("/usr/bin/python3", X_OK) != 0) {
        SKIP("/usr/bin/python3 is missing: HTML report not tested");
        CHECK_DONE("test_report");
    }
    fflush(stdout);
    execl("/usr/bin/python3", "python3", "tests/test_report.py", (char *)NULL);
    CHECK(0, "cannot run /usr/bin/python3 tests/test_report.py");
    CHECK_DONE("test_report");
}
