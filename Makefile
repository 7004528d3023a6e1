# vdt - one non-recursive GNU Makefile.
#
#   make            build build/libvdt.a and bin/vdt-*
#   make check      install what is missing, build, run every test
#   make demo       install what is missing, build, run the main pipeline
#   make bench      benchmarks against peers on real models
#   make fuzz       run each libFuzzer target briefly (FUZZ_SECONDS)
#   make install    PREFIX=/usr/local DESTDIR= MANDIR=$(PREFIX)/share/man
#   make SANITIZE=1 check   the same with ASan and UBSan

CC ?= cc
CXX ?= c++
# -O3 gives the same output bytes as -O2 (no -ffast-math, no FMA) and,
# in alternating runs, takes 7-8% off vdt-qslim's time on the dragon and
# on a 1M-triangle mesh (10% fewer instructions), a fifth off phase I of
# vdt-cluster on big-20m, and a little off vdt-measure on the dragon.
CFLAGS ?= -O3 -g
CXXFLAGS ?= -O2 -g
PREFIX ?= /usr/local
BINDIR ?= $(PREFIX)/bin
# The tools look for their modules beside themselves and in ../lib/vdt
# from there (lib/io/module.h): where they go follows BINDIR, and is no
# setting of its own, which the installed tools would not find.
ifeq ($(origin MODDIR),command line)
$(error MODDIR is not a setting: the modules go in lib/vdt beside BINDIR, where the tools look)
endif
MODDIR = $(dir $(patsubst %/,%,$(BINDIR)))lib/vdt
MANDIR ?= $(PREFIX)/share/man
FUZZ_SECONDS ?= 15

override CPPFLAGS += -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE
override CFLAGS += -std=c11 -Wall -Wextra -Werror -MMD -MP
override CXXFLAGS += -std=c++17 -Wall -Wextra -Werror -MMD -MP \
	-Wno-deprecated-declarations -Wno-deprecated-copy
LDLIBS_VDT = -Wl,--as-needed -lz -lm -lpthread -ldl
# Modules the tools load at their first use (lib/io/module.h). OpenImageIO
# at the first image: its libraries cost a third of a second and ~130 MB
# at start-up. Draco at the first .drc mesh: with the C++ runtime, 3.5 MB
# resident and about 1.3 ms, which every start would pay if it were linked
# (a run without it: 2.2 MB). Assimp at the first skinned model: about
# 9 MB and 2.6 ms, which every start of vdt-deform would pay.
LDLIBS_vdt-image = -lOpenImageIO -lOpenImageIO_Util
LDLIBS_vdt-draco = -ldraco
LDLIBS_vdt-assimp = -lassimp

ifeq ($(SANITIZE),1)
VARIANT := san
SAN := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
override CFLAGS += $(SAN)
override CXXFLAGS += $(SAN)
override LDFLAGS += $(SAN)
else
VARIANT := rel
endif

B := build/$(VARIANT)

# Objects are compiled again when the flags change (a CFLAGS of the
# user's, a new default): each variant keeps those it was built with in
# $(B)/flags, written here, as the makefile is read (a rule's copy would
# take the target-specific flags of whichever object asked first).
FLAGS_NOW := $(CC) $(CPPFLAGS) $(CFLAGS) | $(CXX) $(CXXFLAGS)
ifneq ($(FLAGS_NOW),$(file <$(B)/flags))
$(shell mkdir -p $(B))
$(file >$(B)/flags,$(FLAGS_NOW))
endif

LIB_C := $(sort $(wildcard lib/*.c lib/io/*.c))
LIB_CC := $(sort $(wildcard lib/io/*.cc))
LIB_O := $(LIB_C:%.c=$(B)/%.o) $(LIB_CC:%.cc=$(B)/%.o)
LIB := $(B)/libvdt.a
COMMON_O := $(B)/cmd/common.o
TOOLS := $(patsubst cmd/%.c,bin/%,$(sort $(wildcard cmd/vdt-*.c)))
UNIT := $(patsubst tests/unit/%.c,$(B)/tests/%,$(sort $(wildcard tests/unit/test_*.c)))
HELPERS := $(patsubst scripts/%.c,$(B)/scripts/%,$(sort $(wildcard scripts/*.c)))
BENCH := $(patsubst scripts/bench/%.c,$(B)/bench/%,$(sort $(wildcard scripts/bench/*.c))) \
	$(patsubst scripts/bench/%.cc,$(B)/bench/%,$(sort $(wildcard scripts/bench/*.cc)))
MAN1 := $(sort $(wildcard man/*.1))
MAN57 := $(sort $(wildcard man/*.5 man/*.7))

.PHONY: all deps check unit cli demo bench fuzz samples install uninstall \
	clean lint helpers FORCE
.SUFFIXES:
.DELETE_ON_ERROR:
.SECONDARY:

MODULES := bin/vdt-image.so bin/vdt-draco.so bin/vdt-assimp.so

all: $(TOOLS) $(MODULES) helpers

helpers: $(HELPERS)

# The binaries in bin/ are of one variant at a time: relink when it changes.
build/variant: FORCE
	@mkdir -p build
	@echo $(VARIANT) | cmp -s - $@ || echo $(VARIANT) > $@
FORCE:

$(B)/%.o: %.c $(B)/flags
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c -o $@ $<

$(B)/%.o: %.cc $(B)/flags
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c -o $@ $<

# Where the build leaves the modules: the last place a tool looks.
$(B)/lib/io/module.o: override CPPFLAGS += -DVDT_MODULE_BUILT_DIR='"$(CURDIR)/bin"'
$(B)/lib/io/%.o: override CXXFLAGS += -fPIC
bin/vdt-image.so: $(B)/lib/io/imagemod/vdt-image.o build/variant
bin/vdt-draco.so: $(B)/lib/io/dracomod/vdt-draco.o build/variant
bin/vdt-assimp.so: $(B)/lib/io/assimpmod/vdt-assimp.o build/variant
$(MODULES):
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -shared -o $@ $< $(LDLIBS_$(basename $(@F)))

$(LIB): $(LIB_O)
	@mkdir -p $(@D)
	rm -f $@
	$(AR) rcs $@ $^

bin/%: $(B)/cmd/%.o $(COMMON_O) $(LIB) build/variant
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) -o $@ $< $(COMMON_O) $(LIB) $(LDLIBS_VDT)

$(B)/tests/%: $(B)/tests/unit/%.o $(LIB)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) -o $@ $< $(LIB) -lcmocka $(LDLIBS_VDT)

$(B)/scripts/%: $(B)/scripts/%.o $(LIB)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) -o $@ $< $(LIB) $(LDLIBS_VDT)

# Comparison drivers for the bench: each links one peer library.
BENCH_LIBS_meshopt = -lmeshoptimizer
BENCH_LIBS_cgal = -lgmp -lmpfr
BENCH_LIBS_openmesh = -lOpenMeshTools -lOpenMeshCore
BENCH_LIBS_vtk = -lvtkFiltersCore-9.1 -lvtkCommonExecutionModel-9.1 -lvtkCommonDataModel-9.1 -lvtkCommonCore-9.1 -lvtksys-9.1
$(B)/scripts/bench/vtk_%.o: override CXXFLAGS += -isystem /usr/include/vtk-9.1
# CGAL's Garland-Heckbert policies include <Eigen/Dense> (libeigen3-dev).
$(B)/scripts/bench/cgal_%.o: override CXXFLAGS += -isystem /usr/include/eigen3
$(B)/bench/%: $(B)/scripts/bench/%.o $(LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) -o $@ $< $(LIB) $(BENCH_LIBS_$(firstword $(subst _, ,$*))) $(LDLIBS_VDT)

deps:
	@scripts/install-deps

unit: $(UNIT) $(B)/tests/failalloc.so

# An LD_PRELOAD library that makes the Nth allocation fail, for the tests
# of running out of memory: not sanitized (ASan's allocator must come
# first; the tests skip it there).
$(B)/tests/failalloc.so: tests/cli/failalloc.c
	@mkdir -p $(@D)
	$(CC) -std=c11 -O2 -Wall -Wextra -Werror -shared -fPIC -o $@ $<

check: deps
	@$(MAKE) --no-print-directory all unit samples
	@scripts/run-tests $(B)/tests

samples: deps helpers
	@scripts/fetch-samples

demo: deps
	@$(MAKE) --no-print-directory all samples
	@scripts/demo

bench: deps
	@$(MAKE) --no-print-directory all samples $(BENCH)
	@scripts/bench/run $(B)/bench

# libFuzzer targets: clang, with the library built again for coverage.
F := build/fuzz
# (-MMD -MP: their own dependency files, which the include at the end
# reads, so that a changed header rebuilds them as it does the others)
FUZZ_FLAGS := -g -O1 -fsanitize=fuzzer-no-link,address,undefined -MMD -MP
FUZZ_LIB_O := $(LIB_C:%.c=$(F)/%.o) $(LIB_CC:%.cc=$(F)/%.o)
FUZZERS := $(patsubst tests/fuzz/%.c,$(F)/%,$(sort $(wildcard tests/fuzz/fuzz_*.c)))
# (objects made before they had them are made again once, being older
# than this stamp)
$(F)/deps.stamp:
	@mkdir -p $(@D) && touch $@
$(FUZZ_LIB_O) $(FUZZERS:$(F)/%=$(F)/tests/fuzz/%.o): $(F)/deps.stamp
$(F)/%.o: %.c
	@mkdir -p $(@D)
	clang $(CPPFLAGS) -std=c11 -Wall -Wextra $(FUZZ_FLAGS) -c -o $@ $<
$(F)/%.o: %.cc
	@mkdir -p $(@D)
	clang++ $(CPPFLAGS) -std=c++17 -Wall -Wno-deprecated-declarations $(FUZZ_FLAGS) -c -o $@ $<
$(F)/fuzz_%: $(F)/tests/fuzz/fuzz_%.o $(FUZZ_LIB_O)
	clang++ -fsanitize=fuzzer,address,undefined -o $@ $^ $(LDLIBS_VDT)
# The Draco module beside the fuzzers, instrumented as they are: .drc data
# is fuzzed through it as through a tool.
$(F)/lib/io/dracomod/%.o: FUZZ_FLAGS += -fPIC
$(F)/vdt-draco.so: $(F)/lib/io/dracomod/vdt-draco.o
	clang++ -fsanitize=address,undefined -shared -o $@ $< $(LDLIBS_vdt-draco)
fuzz: deps $(FUZZERS) $(F)/vdt-draco.so
	@scripts/run-fuzz $(F) $(FUZZ_SECONDS)

lint:
	mandoc -Tlint -W warning $(MAN1) $(MAN57)

install: all
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(MANDIR)/man1 \
		$(DESTDIR)$(MANDIR)/man5 $(DESTDIR)$(MANDIR)/man7
	install -m 755 $(TOOLS) $(DESTDIR)$(BINDIR)
	install -d $(DESTDIR)$(MODDIR)
	install -m 644 $(MODULES) $(DESTDIR)$(MODDIR)
	$(if $(wildcard scripts/vdt-batch),install -m 755 scripts/vdt-batch $(DESTDIR)$(BINDIR))
	install -m 644 $(MAN1) $(DESTDIR)$(MANDIR)/man1
	$(if $(wildcard man/*.5),install -m 644 $(wildcard man/*.5) $(DESTDIR)$(MANDIR)/man5)
	$(if $(wildcard man/*.7),install -m 644 $(wildcard man/*.7) $(DESTDIR)$(MANDIR)/man7)

uninstall:
	rm -f $(addprefix $(DESTDIR)$(BINDIR)/,$(notdir $(TOOLS)) vdt-batch)
	rm -f $(addprefix $(DESTDIR)$(MODDIR)/,$(notdir $(MODULES)))
	rmdir --ignore-fail-on-non-empty $(DESTDIR)$(MODDIR) 2>/dev/null || :
	rm -f $(addprefix $(DESTDIR)$(MANDIR)/man1/,$(notdir $(MAN1)))
	rm -f $(addprefix $(DESTDIR)$(MANDIR)/man5/,$(notdir $(wildcard man/*.5)))
	rm -f $(addprefix $(DESTDIR)$(MANDIR)/man7/,$(notdir $(wildcard man/*.7)))

clean:
	rm -rf build bin

-include $(shell find build -name '*.d' 2>/dev/null)
