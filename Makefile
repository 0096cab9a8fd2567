# quad2nurbs — plain Makefile.  Folders under src/ are pipeline stages; every src/*/*.c except
# src/cli/ goes into build/libquad2nurbs.a, src/*/*.cpp are the thin C++ shims over dependencies
# whose API is C++ (Ceres).  tests/test_*.c are unit/integration tests against the library;
# tests/ref_*.cpp are reference programs that call OpenSubdiv / OpenCASCADE.  A new test program
# is one file: tests/test_NAME.c (or tests/ref_NAME.cpp) is built and run by make check; extra
# libraries, if any, go in one line LDLIBS_test_NAME := ... below.
#   make            library + executable          make check       quick tests (long sweeps left out)
#   make check-full all tests + fuzz-check (CI)      make demo        main job on the demo mesh
#   make bench      benchmarks (not tests)        make install PREFIX=/usr/local DESTDIR=
#   make sweep      unseen generated meshes against the issues' targets (BASE=older binary: side by side)
#   (install: binary, libquad2nurbs.a, include/quad2nurbs.h, lib/pkgconfig/quad2nurbs.pc)
#   make fuzz       libFuzzer harnesses (clang)   make fuzz-check  run each for FUZZ_SECONDS (60)
#   make CONFIG=debug|asan                        (default: release)
#   make check TESTS="test_cli test_mesh" JOBS=2  run some programs only / N at a time
#
# Flags: the caller's CPPFLAGS, CFLAGS, CXXFLAGS, LDFLAGS and LDLIBS (environment or command
# line, as Debian packaging passes them) are honoured and come after the project's Q2N_*FLAGS,
# so they win; CONFIG only chooses the default CFLAGS/CXXFLAGS for a caller who sets none.

CONFIG   ?= release
PREFIX   ?= /usr/local
CC       ?= cc
CXX      ?= c++
BUILD    := build

ifeq ($(CONFIG),debug)
  OPT := -O0 -g
else ifeq ($(CONFIG),asan)
  OPT := -O1 -g
  SAN := -fsanitize=address,undefined -fno-omit-frame-pointer
else
  OPT := -O3 -g
endif
CFLAGS   ?= $(OPT)
CXXFLAGS ?= $(OPT)

Q2N_CPPFLAGS += -Isrc -Iinclude -MMD -MP
Q2N_CFLAGS   += -std=c11 -Wall -Wextra -D_POSIX_C_SOURCE=200809L -D_ISOC11_SOURCE $(SAN)
Q2N_CXXFLAGS += -std=c++17 -Wall -Wextra -I/usr/include/eigen3 $(SAN)
Q2N_LDFLAGS  += $(SAN)

LIB_C    := $(filter-out src/cli/%,$(wildcard src/*/*.c))
LIB_CXX  := $(wildcard src/*/*.cpp)
CLI_C    := $(wildcard src/cli/*.c)
LIB_OBJ  := $(LIB_C:%.c=$(BUILD)/%.o) $(LIB_CXX:%.cpp=$(BUILD)/%.o)
CLI_OBJ  := $(CLI_C:%.c=$(BUILD)/%.o)
LIB      := $(BUILD)/libquad2nurbs.a
EXE      := $(BUILD)/quad2nurbs

# Ceres (and its glog) only when the fit shim is part of the library.
ifneq ($(LIB_CXX),)
  DEPLIBS := -lceres -lglog -lgflags -lstdc++ -lpthread
endif
Q2N_LDLIBS := $(DEPLIBS) -lcholmod -lsuitesparseconfig -llapack -lblas -lm
COMPILE_C    = $(CC) $(Q2N_CPPFLAGS) $(CPPFLAGS) $(Q2N_CFLAGS) $(CFLAGS)
COMPILE_CXX  = $(CXX) $(Q2N_CPPFLAGS) $(CPPFLAGS) $(Q2N_CXXFLAGS) $(CXXFLAGS)
LINK_FLAGS   = $(Q2N_LDFLAGS) $(LDFLAGS)

TEST_C   := $(wildcard tests/test_*.c)
TEST_BIN := $(TEST_C:tests/%.c=$(BUILD)/tests/%)
REF_CXX  := $(wildcard tests/ref_*.cpp)
REF_BIN  := $(REF_CXX:tests/%.cpp=$(BUILD)/tests/%)
# Example programs (examples/*.c): the public header only (-Iinclude, no -Isrc), built by make
# check and run by tests/test_install.c, which also builds them against an installed copy.
EXAMPLE_C   := $(wildcard examples/*.c)
EXAMPLE_BIN := $(EXAMPLE_C:examples/%.c=$(BUILD)/examples/%)
# The version lives in include/quad2nurbs.h (Q2N_VERSION_MAJOR/MINOR/PATCH).
VERSION  := $(shell sed -n 's/^\#define Q2N_VERSION_MAJOR \([0-9]*\).*/\1/p; s/^\#define Q2N_VERSION_MINOR \([0-9]*\).*/\1/p; s/^\#define Q2N_VERSION_PATCH \([0-9]*\).*/\1/p' include/quad2nurbs.h | paste -sd.)
BENCH_C  := $(wildcard bench/*.c)
BENCH_CXX:= $(wildcard bench/*.cpp)
BENCH_BIN:= $(BENCH_C:bench/%.c=$(BUILD)/bench/%) $(BENCH_CXX:bench/%.cpp=$(BUILD)/bench/%)
REFLIBS  := -losdCPU -lTKSTEP -lTKSTEPBase -lTKIGES -lTKXSBase -lTKGeomAlgo -lTKGeomBase \
            -lTKBRep -lTKG3d -lTKG2d -lTKMath -lTKernel
OCCT_INC := -I/usr/include/opencascade

# Fuzzing (not part of `make check`; needs Debian clang and libclang-rt-14-dev): the library
# again with clang, ASan, UBSan and libFuzzer's coverage into $(FUZZ_DIR), the harnesses of
# tests/fuzz/ linked against it.  `make fuzz-check` runs each for FUZZ_SECONDS (docs/fuzz.md).
FUZZ_CC      ?= clang
FUZZ_CXX     ?= clang++
FUZZ_DIR     := $(BUILD)/fuzz
FUZZ_SECONDS ?= 60
FUZZ_SAN     := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
FUZZ_CFLAGS  := -std=c11 -O1 -g $(FUZZ_SAN) -fsanitize=fuzzer-no-link -D_POSIX_C_SOURCE=200809L -D_ISOC11_SOURCE
FUZZ_CXXFLAGS:= -std=c++17 -O1 -g $(FUZZ_SAN) -fsanitize=fuzzer-no-link -I/usr/include/eigen3
FUZZ_LIB_OBJ := $(LIB_C:%.c=$(FUZZ_DIR)/%.o) $(LIB_CXX:%.cpp=$(FUZZ_DIR)/%.o)
FUZZ_BIN     := $(FUZZ_DIR)/fuzz_obj $(FUZZ_DIR)/fuzz_model


JOBS     ?= $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 2)
TESTS    ?=

.PHONY: all lib check check-full demo bench sweep install clean deps fuzz fuzz-check
all: $(EXE)
lib: $(LIB)

$(LIB): $(LIB_OBJ)
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^

$(EXE): $(CLI_OBJ) $(LIB)
	$(CC) $(Q2N_CFLAGS) $(CFLAGS) $(LINK_FLAGS) -o $@ $(CLI_OBJ) $(LIB) $(Q2N_LDLIBS) $(LDLIBS)

$(BUILD)/%.o: %.c
	@mkdir -p $(@D)
	$(COMPILE_C) -c $< -o $@

$(BUILD)/%.o: %.cpp
	@mkdir -p $(@D)
	$(COMPILE_CXX) -c $< -o $@

# Test, reference and benchmark programs: one source file each, linked with the library (and
# LDLIBS_<program> when a program sets it).
$(BUILD)/tests/%: tests/%.c $(LIB)
	@mkdir -p $(@D)
	$(COMPILE_C) -Itests $(LINK_FLAGS) $< -o $@ $(LIB) $(LDLIBS_$*) $(Q2N_LDLIBS) $(LDLIBS)

$(BUILD)/tests/ref_%: tests/ref_%.cpp $(LIB)
	@mkdir -p $(@D)
	$(COMPILE_CXX) $(OCCT_INC) -Itests $(LINK_FLAGS) $< -o $@ $(LIB) $(LDLIBS_ref_$*) $(REFLIBS) $(Q2N_LDLIBS) $(LDLIBS)

$(BUILD)/examples/%: examples/%.c include/quad2nurbs.h $(LIB)
	@mkdir -p $(@D)
	$(CC) -Iinclude -MMD -MP $(CPPFLAGS) $(Q2N_CFLAGS) $(CFLAGS) $(LINK_FLAGS) $< -o $@ $(LIB) $(Q2N_LDLIBS) $(LDLIBS)

$(BUILD)/bench/%: bench/%.c $(LIB)
	@mkdir -p $(@D)
	$(COMPILE_C) -Itests $(LINK_FLAGS) $< -o $@ $(LIB) $(Q2N_LDLIBS) $(LDLIBS)

$(BUILD)/bench/%: bench/%.cpp $(LIB)
	@mkdir -p $(@D)
	$(COMPILE_CXX) $(OCCT_INC) -Itests $(LINK_FLAGS) $< -o $@ $(LIB) $(REFLIBS) $(Q2N_LDLIBS) $(LDLIBS)

# make check: the quick tests; make check-full: the same programs with their long sweeps
# (Q2N_TEST_FULL=1).  tests/run_tests.sh runs JOBS programs at a time (TESTS: only those).
check: $(EXE) $(TEST_BIN) $(REF_BIN) $(EXAMPLE_BIN)
	@sh tests/run_tests.sh -j $(JOBS) --build $(BUILD) $(TESTS)

check-full: $(EXE) $(TEST_BIN) $(REF_BIN) $(EXAMPLE_BIN)
	@sh tests/run_tests.sh --full -j $(JOBS) --build $(BUILD) $(TESTS)
	@if [ -n "$(TESTS)" ]; then :; elif command -v $(FUZZ_CC) >/dev/null 2>&1; then \
	  $(MAKE) --no-print-directory fuzz-check; \
	else echo "SKIP fuzz-check: $(FUZZ_CC) is not installed (apt-get install -y clang libclang-rt-14-dev)"; \
	  [ -z "$$Q2N_REQUIRE_SHARED" ]; fi

demo: $(EXE)
	@sh tools/demo.sh $(EXE)

bench: $(EXE) $(BENCH_BIN)
	@sh bench/run_bench.sh $(BUILD)

# make sweep [BASE=path/to/older/quad2nurbs]: the generalisation sweep (bench/sweep.py), meshes no
# test has seen against the issues' targets, before/after when BASE is given (a few minutes)
sweep: $(EXE)
	@/usr/bin/python3 bench/sweep.py $(EXE) --out $(BUILD)/sweep $(if $(BASE),--base $(BASE))

deps:
	@sh tools/install-deps.sh

$(FUZZ_DIR)/src/%.o: src/%.c
	@mkdir -p $(@D)
	$(FUZZ_CC) $(Q2N_CPPFLAGS) $(CPPFLAGS) $(FUZZ_CFLAGS) -c $< -o $@

$(FUZZ_DIR)/src/%.o: src/%.cpp
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(Q2N_CPPFLAGS) $(CPPFLAGS) $(FUZZ_CXXFLAGS) -c $< -o $@

$(FUZZ_DIR)/libquad2nurbs.a: $(FUZZ_LIB_OBJ)
	rm -f $@ && ar rcs $@ $^

$(FUZZ_DIR)/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_common.h $(FUZZ_DIR)/libquad2nurbs.a
	$(FUZZ_CC) $(Q2N_CPPFLAGS) -Itests $(CPPFLAGS) $(FUZZ_CFLAGS) -DQ2N_LIBFUZZER -c $< -o $@.o
	$(FUZZ_CXX) -fsanitize=fuzzer $(FUZZ_SAN) -o $@ $@.o $(FUZZ_DIR)/libquad2nurbs.a $(Q2N_LDLIBS)

fuzz: $(FUZZ_BIN)

fuzz-check: $(FUZZ_BIN)
	@sh tests/fuzz/run_fuzz.sh $(FUZZ_DIR) $(FUZZ_SECONDS)

# make install [PREFIX=/usr/local] [DESTDIR=staging]: the command, the static library, the public
# header and a pkg-config file (the library is static: link with pkg-config --static, which adds
# its dependencies from Libs.private).
install: $(EXE) $(LIB)
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include
	install -m 755 $(EXE) $(DESTDIR)$(PREFIX)/bin/quad2nurbs
	install -m 644 $(LIB) $(DESTDIR)$(PREFIX)/lib/libquad2nurbs.a
	install -m 644 include/quad2nurbs.h $(DESTDIR)$(PREFIX)/include/quad2nurbs.h
	printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$${prefix}/lib' 'includedir=$${prefix}/include' '' \
	  'Name: quad2nurbs' \
	  'Description: smooth interpolating surfaces on quad meshes, fitted B-splines, IGES and STEP' \
	  'Version: $(VERSION)' 'Cflags: -I$${includedir}' 'Libs: -L$${libdir} -lquad2nurbs' \
	  'Libs.private: $(Q2N_LDLIBS)' > $(DESTDIR)$(PREFIX)/lib/pkgconfig/quad2nurbs.pc
	chmod 644 $(DESTDIR)$(PREFIX)/lib/pkgconfig/quad2nurbs.pc

clean:
	rm -rf $(BUILD)

# Header dependencies of every object and program (-MMD writes them beside each output).
-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_BIN:=.d) $(REF_BIN:=.d) $(BENCH_BIN:=.d) $(FUZZ_LIB_OBJ:.o=.d) \
         $(EXAMPLE_BIN:=.d)
