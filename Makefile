# quad2nurbs — plain Makefile.  Folders under src/ are pipeline stages; every src/*/*.c except
# src/cli/ goes into build/libquad2nurbs.a, src/*/*.cpp are the thin C++ shims over dependencies
# whose API is C++ (Ceres).  tests/test_*.c are unit/integration tests against the library;
# tests/ref_*.cpp are reference programs that call OpenSubdiv / OpenCASCADE.
#   make            library + executable          make check   build and run all tests
#   make demo       run the main job on the bundled demo mesh
#   make bench      benchmarks (not tests)        make install PREFIX=/usr/local
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
LDLIBS   := $(DEPLIBS) -lcholmod -llapack -lblas -lm $(LDASAN)

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

.PHONY: all lib check demo bench install clean deps
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

install: $(EXE) $(LIB)
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/lib $(DESTDIR)$(PREFIX)/include
	install -m 755 $(EXE) $(DESTDIR)$(PREFIX)/bin/quad2nurbs
	install -m 644 $(LIB) $(DESTDIR)$(PREFIX)/lib/libquad2nurbs.a
	install -m 644 include/quad2nurbs.h $(DESTDIR)$(PREFIX)/include/quad2nurbs.h

clean:
	rm -rf $(BUILD)

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d)
