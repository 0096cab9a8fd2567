# quad2nurbs — plain Makefile.  Folders under src/ are pipeline stages; every src/*/*.c except
# src/cli/ goes into build/libquad2nurbs.a, src/*/*.cpp are the thin C++ shims over dependencies
# whose API is C++ (Ceres).  tests/test_*.c are unit/integration tests against the library;
# tests/ref_*.cpp are reference programs that call OpenSubdiv / OpenCASCADE.
#   make            library + executable          make check   build and run all tests
#   make demo       run the main job on the bundled demo mesh
#   make bench      benchmarks (not tests)        make install PREFIX=/usr/local
#   make fuzz       libFuzzer harnesses (clang)   make fuzz-check  run each for FUZZ_SECONDS (60)
#   make CONFIG=debug|asan                        (default: release)

CONFIG   ?= release
PREFIX   ?= /usr/local
CC       ?= cc
CXX      ?= c++
BUILD    := build

CPPFLAGS := -Isrc -Iinclude -MMD -MP
WARN     := -Wall -Wextra
ifeq ($(CONFIG),debug)
  OPT := -O0 -g
else ifeq ($(CONFIG),asan)
  OPT := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer
  LDASAN := -fsanitize=address,undefined
else
  OPT := -O2 -g
endif
CFLAGS   := -std=c11 $(WARN) $(OPT) -D_POSIX_C_SOURCE=200809L -D_ISOC11_SOURCE
CXXFLAGS := -std=c++17 $(WARN) $(OPT) -I/usr/include/eigen3

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
LDLIBS   := $(DEPLIBS) -lm $(LDASAN)

TEST_C   := $(wildcard tests/test_*.c)
TEST_BIN := $(TEST_C:tests/%.c=$(BUILD)/tests/%)
REF_CXX  := $(wildcard tests/ref_*.cpp)
REF_BIN  := $(REF_CXX:tests/%.cpp=$(BUILD)/tests/%)
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

.PHONY: all lib check demo bench install clean deps fuzz fuzz-check
all: $(EXE)
lib: $(LIB)

$(LIB): $(LIB_OBJ)
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^

$(EXE): $(CLI_OBJ) $(LIB)
	$(CC) $(OPT) -o $@ $(CLI_OBJ) $(LIB) $(LDLIBS)

$(BUILD)/%.o: %.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/%.o: %.cpp
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c $< -o $@

$(BUILD)/tests/%: tests/%.c $(LIB)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -Itests $< -o $@ $(LIB) $(LDLIBS)

$(BUILD)/tests/ref_%: tests/ref_%.cpp $(LIB)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) $(OCCT_INC) -Itests $< -o $@ $(LIB) $(REFLIBS) $(LDLIBS)

$(BUILD)/bench/%: bench/%.c $(LIB)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -Itests $< -o $@ $(LIB) $(LDLIBS)

$(BUILD)/bench/%: bench/%.cpp $(LIB)
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) $(OCCT_INC) -Itests $< -o $@ $(LIB) $(REFLIBS) $(LDLIBS)

check: $(EXE) $(TEST_BIN) $(REF_BIN)
	@sh tests/run_tests.sh $(BUILD)

demo: $(EXE)
	@sh tools/demo.sh $(EXE)

bench: $(EXE) $(BENCH_BIN)
	@sh bench/run_bench.sh $(BUILD)

deps:
	@sh tools/install-deps.sh

$(FUZZ_DIR)/src/%.o: src/%.c
	@mkdir -p $(@D)
	$(FUZZ_CC) $(CPPFLAGS) $(FUZZ_CFLAGS) -c $< -o $@

$(FUZZ_DIR)/src/%.o: src/%.cpp
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(CPPFLAGS) $(FUZZ_CXXFLAGS) -c $< -o $@

$(FUZZ_DIR)/libquad2nurbs.a: $(FUZZ_LIB_OBJ)
	rm -f $@ && ar rcs $@ $^

$(FUZZ_DIR)/fuzz_%: tests/fuzz/fuzz_%.c tests/fuzz/fuzz_common.h $(FUZZ_DIR)/libquad2nurbs.a
	$(FUZZ_CC) $(CPPFLAGS) $(FUZZ_CFLAGS) -DQ2N_LIBFUZZER -c $< -o $@.o
	$(FUZZ_CXX) -fsanitize=fuzzer $(FUZZ_SAN) -o $@ $@.o $(FUZZ_DIR)/libquad2nurbs.a $(DEPLIBS) -lm

fuzz: $(FUZZ_BIN)

fuzz-check: $(FUZZ_BIN)
	@sh tests/fuzz/run_fuzz.sh $(FUZZ_DIR) $(FUZZ_SECONDS)

install: $(EXE) $(LIB)
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/include
	install -m 755 $(EXE) $(DESTDIR)$(PREFIX)/bin/quad2nurbs
	install -m 644 $(LIB) $(DESTDIR)$(PREFIX)/lib/libquad2nurbs.a
	install -m 644 include/quad2nurbs.h $(DESTDIR)$(PREFIX)/include/quad2nurbs.h

clean:
	rm -rf $(BUILD)

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(FUZZ_LIB_OBJ:.o=.d)
