# largesteps - build, test and install.
#
#   make                    build/liblargesteps.a and build/largesteps (gcc, ls_real = double)
#   make REAL=float         the float build of the same
#   make test               the whole native test matrix, lint and install checks;
#                           ends with one line "N passed, M failed"
#   make check              build and run the tests of one variant (CC, REAL, SAN, BUILD)
#   make run                print the library's configuration
#   make examples           build the programs of examples/ ($(BUILD)/examples/)
#   make install PREFIX=... install the library, headers, config.h and a pkg-config file
#   make bench              benchmarks (tables in build/bench/)
#   make bench-fit          the fit suite: default fits on 14 public targets (build/bench/fit_suite.md)
#   make cross              every emulated target (aarch64, armhf, riscv64, s390x,
#                           i686; float and double) under qemu-user: tests + digest
#   make m4                 the Cortex-M4 port under qemu-system-arm (mps2-an386):
#                           digest, MCU profile, no double arithmetic in the float build
#   make size               code size per module, Cortex-M4 float -Os build, checked
#                           against fixtures/size-cortex-m4.txt
#   make digest-update      rewrite fixtures/digest-{double,float,float-floatsums}.txt from this machine
#
# Variables: CC (gcc or clang), REAL (double or float), SAN=1 (ASan+UBSan),
# BUILD (output directory), ARCHFLAGS (extra target flags, e.g. for cross builds),
# RUNNER (prefix to run test programs, e.g. "qemu-aarch64 -L /usr/aarch64-linux-gnu"),
# TARGET (aarch64, armhf, riscv64, s390x, i686, cortex-m4: sets CC, AR, NM, SIZE,
# ARCHFLAGS, RUNNER and BUILD=build/TARGET-REAL, e.g. `make check TARGET=s390x REAL=float`),
# PROFILE (cortex-m4 only: full = the board's 4 MiB RAM, mcu = 256 KiB RAM, 8 KiB stack).

CC       ?= cc
CXX      ?= c++
AR       ?= ar
NM       ?= nm
SIZE     ?= size
REAL     ?= double
# SUMS: the type of the LDLT's sums (factorization and solves) in the float
# build: double (default; L and D are stored in float, the unrefined backward
# error stays below 1e-6) or real (float sums: for FPUs without double, the
# Cortex-M4's default). No effect in the double build.
SUMS     ?=
TARGET   ?=
PROFILE  ?= full
# TARGET is a make variable only: a TARGET in the environment is ignored.
ifeq ($(origin TARGET),environment)
TARGET   :=
endif
PREFIX   ?= /usr/local
SAN      ?=
ARCHFLAGS ?=
RUNNER   ?=

# --- targets ----------------------------------------------------------------
# Emulated Linux targets: Debian's gcc cross compilers, run under qemu-user with
# the target's libc (packages: .ci/packages/cross.txt). Flags that make
# FLT_EVAL_METHOD 0 (core.h refuses anything else): s390x evaluates float in
# double in ISO C mode, i686 defaults to the x87.
CROSS_TARGETS    := aarch64 armhf riscv64 s390x i686
triple_aarch64   := aarch64-linux-gnu
triple_armhf     := arm-linux-gnueabihf
triple_riscv64   := riscv64-linux-gnu
triple_s390x     := s390x-linux-gnu
triple_i686      := i686-linux-gnu
triple_cortex-m4 := arm-none-eabi
qemu_aarch64     := qemu-aarch64
qemu_armhf       := qemu-arm
qemu_riscv64     := qemu-riscv64
qemu_s390x       := qemu-s390x
qemu_i686        := qemu-i386
flags_s390x      := -fexcess-precision=fast
# The worst call chain of a public function (tests/hygiene.sh): 4096 bytes,
# measured on every target; s390x's ABI puts a 160-byte register save area
# in every frame, so its chains are checked against 5120.
STACK_BUDGET     := $(if $(filter s390x,$(TARGET)),5120,4096)
# i686 also: no PIE (its __x86.get_pc_thunk.* helpers are global symbols
# without the ls_ prefix) and fixed-size outgoing-argument areas (pushed
# arguments make gcc's call graph report dynamic frames).
flags_i686       := -msse2 -mfpmath=sse -fno-pie -no-pie -maccumulate-outgoing-args
# Cortex-M4F: single-precision FPU only; double arithmetic is soft float.
flags_cortex-m4  := -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 \
                    -ffunction-sections -fdata-sections
HOSTED := 1
PORT_DIR := port/posix
ifneq ($(TARGET),)
ifeq ($(filter $(TARGET),$(CROSS_TARGETS) cortex-m4),)
$(error TARGET must be one of $(CROSS_TARGETS) cortex-m4, not '$(TARGET)')
endif
TRIPLE := $(triple_$(TARGET))
ifneq ($(origin CC),command line)
CC := $(TRIPLE)-gcc
endif
ifneq ($(origin AR),command line)
AR := $(TRIPLE)-ar
endif
ifneq ($(origin NM),command line)
NM := $(TRIPLE)-nm
endif
ifneq ($(origin SIZE),command line)
SIZE := $(TRIPLE)-size
endif
# The host's C++ compiler checks that the headers parse as C++ (no target code).
ifneq ($(origin CXX),command line)
CXX := g++
endif
ifneq ($(origin ARCHFLAGS),command line)
ARCHFLAGS := $(flags_$(TARGET))
endif
ifeq ($(TARGET),cortex-m4)
HOSTED   := 0
PORT_DIR := port/cortex-m4
BUILD    ?= build/cortex-m4-$(PROFILE)-$(REAL)
ifeq ($(origin RUNNER),file)
RUNNER   := sh tests/tools/run_m4.sh
endif
else
BUILD    ?= build/$(TARGET)-$(REAL)
# LS_TEST_EMULATED=1 tells a test program it runs under an emulator (it may
# shrink its own loops).
ifeq ($(origin RUNNER),file)
RUNNER   := env LS_TEST_EMULATED=1 $(qemu_$(TARGET)) -L /usr/$(TRIPLE)
endif
endif
endif
BUILD    ?= build

ifeq ($(filter $(REAL),double float),)
$(error REAL must be double or float, not '$(REAL)')
endif
REAL_IS_FLOAT := $(if $(filter float,$(REAL)),1,0)
ifeq ($(SUMS),)
SUMS := $(if $(filter cortex-m4,$(TARGET)),real,double)
endif
ifeq ($(filter $(SUMS),double real),)
$(error SUMS must be double or real, not '$(SUMS)')
endif
SUMS_DOUBLE := $(if $(filter double,$(SUMS)),1,0)
VARIANT_NAME  := $(if $(filter float,$(REAL)),largesteps-float,largesteps)

CC_IS_CLANG := $(shell $(CC) --version 2>/dev/null | grep -qi clang && echo 1)
CC_IS_GCC   := $(if $(CC_IS_CLANG),,$(shell $(CC) --version 2>/dev/null | grep -qiE 'gcc|Free Software' && echo 1))

# Per-function stack limit in bytes (whole-call budgets are checked from the call graph).
STACK_LIMIT ?= 1024

WARN := -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wconversion -Wdouble-promotion \
        -Wstrict-prototypes -Wmissing-prototypes -Wvla -Wcast-align
# OPT may be set (make OPT="-O3 -march=native"); the flags that keep the bits,
# -ffp-contract=off and -fno-fast-math, are added after it whatever it says,
# and the flags that would change them are refused.
ifneq ($(origin OPT),command line)
OPT  := -O2
endif
FPFLAGS := -ffp-contract=off -fno-fast-math
NO_BITS := $(filter -ffast-math -Ofast -ffp-contract=fast -ffp-contract=on -funsafe-math-optimizations \
             -fassociative-math -freciprocal-math -ffinite-math-only,$(OPT) $(ARCHFLAGS))
ifneq ($(NO_BITS),)
$(error $(NO_BITS) would make results depend on the build: largesteps keeps the same bits only with -ffp-contract=off and no fast-math; drop it from OPT / ARCHFLAGS)
endif
ifeq ($(CC_IS_CLANG),1)
STACKWARN := -Wframe-larger-than=$(STACK_LIMIT)
else
STACKWARN := -Wstack-usage=$(STACK_LIMIT)
endif
# The per-function stack limit is the project's for its own builds (-O2, and
# -Os on the MCU); a build with other optimization flags (-O0's unshared
# slots, -O3's and AVX-512's spills) reports larger frames as warnings.
ifeq ($(origin OPT),command line)
STACKWARN += -Wno-error=$(if $(filter 1,$(CC_IS_CLANG)),frame-larger-than,stack-usage=)
endif
ifeq ($(CC_IS_GCC),1)
CALLGRAPH := -fcallgraph-info=su
# On x86-64 gcc pushes stack-passed arguments (the 7th and later) by default,
# which makes the caller's frame "dynamic" for the call-graph stack check; a
# fixed outgoing-argument area keeps every frame static (as on i686, below).
# Code generation of the arithmetic is unchanged.
ifneq ($(filter x86_64%,$(shell $(CC) -dumpmachine 2>/dev/null)),)
CALLGRAPH += -maccumulate-outgoing-args
endif
endif
ifeq ($(SAN),1)
OPT       := -O1 -g -fno-omit-frame-pointer \
             -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all
STACKWARN :=
CALLGRAPH :=
LDSAN     := -fsanitize=address,undefined,float-cast-overflow
endif

INCLUDES := -Iinclude -I$(BUILD)/include
CFLAGS_LIB   := $(WARN) $(STACKWARN) $(OPT) $(ARCHFLAGS) $(FPFLAGS) $(INCLUDES)
# Tests and the port print doubles with printf: -Wdouble-promotion does not apply there.
CFLAGS_TEST  := -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wvla $(OPT) $(ARCHFLAGS) $(FPFLAGS) $(INCLUDES) -Itests
# port/posix: the platform layer (files, clock) at the top, the command-line
# program in program/, the paper's experiments and the trade study in
# experiments/. The bare-metal port is one folder.
PORT_DIRS := $(PORT_DIR) $(wildcard $(PORT_DIR)/program $(PORT_DIR)/experiments)
CFLAGS_PORT  := -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wconversion -Wstrict-prototypes \
                -Wmissing-prototypes -Wvla $(OPT) $(ARCHFLAGS) $(FPFLAGS) $(INCLUDES) $(PORT_DIRS:%=-I%)
LDLIBS       := -lm
ifeq ($(HOSTED),1)
LDLIBS       += -pthread # the POSIX port's thread pool (port/posix/parallel.c); the library starts none
endif
LDFLAGS      := $(ARCHFLAGS) $(LDSAN)
ifeq ($(HOSTED),0)
# Bare metal: our own start-up and semihosting system calls (port/cortex-m4),
# newlib for the test programs' printf, the profile's memory map.
CFLAGS_TEST  += -I$(PORT_DIR) -DLS_PORT_CORTEX_M4=1
LDFLAGS      += -nostartfiles --specs=nosys.specs -L$(PORT_DIR) -T$(PROFILE).ld -Wl,--gc-sections
endif

# The library's sources, one folder per layer, lowest first: a file includes
# only headers of its own layer or lower ones (tests/tools/layers.sh checks it).
# Objects keep flat names (the size and stack checks key on the module name).
LAYERS   := base sparse geometry param render io fit
LIB_SRC  := $(foreach l,$(LAYERS),$(sort $(wildcard src/$(l)/*.c)))
LIB_OBJ  := $(addprefix $(BUILD)/obj/src/,$(notdir $(LIB_SRC:.c=.o)))
vpath %.c $(LAYERS:%=src/%)
PORT_SRC := $(filter-out $(PORT_DIR)/program/main.c,$(sort $(foreach d,$(PORT_DIRS),$(wildcard $(d)/*.c))))
PORT_OBJ := $(PORT_SRC:$(PORT_DIR)/%.c=$(BUILD)/obj/port/%.o)
TEST_SRC := $(sort $(wildcard tests/test_*.c))
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
DIGEST   := $(BUILD)/tests/digest
# The float build's LDLT sums change its bits: SUMS=real has its own digests.
DIGEST_FIXTURE := fixtures/digest-$(REAL)$(if $(filter 1,$(REAL_IS_FLOAT)),$(if $(filter real,$(SUMS)),-floatsums)).txt
ifeq ($(HOSTED),1)
CHECK_BIN := $(TEST_BIN)
ifneq ($(TARGET),)
# Emulated targets: all but the programs in tests/tools/cross_skip.txt (too
# slow under QEMU; each line gives the reason).
CROSS_SKIP := $(strip $(shell sed -e 's/\#.*//' tests/tools/cross_skip.txt 2>/dev/null))
CHECK_BIN := $(filter-out $(CROSS_SKIP:%=$(BUILD)/tests/%),$(TEST_BIN))
ifeq ($(DIGEST_ONLY),1)
# The digest and the hygiene checks alone (tests/stage_cross.sh: the test
# programs run under emulation in one precision per target, the digest in both).
CHECK_BIN :=
endif
endif
else
# On the bare-metal port: the MCU-profile workload (tests/test_mcu.c). The
# other test programs need a hosted C library (fenv, files, large buffers).
CHECK_BIN := $(BUILD)/tests/test_mcu
endif
HEADERS  := include/largesteps.h $(sort $(wildcard include/largesteps/*.h))
CONFIG_H := $(BUILD)/include/largesteps/config.h

LIB      := $(BUILD)/liblargesteps.a
PORTLIB  := $(BUILD)/liblargesteps-posix.a
CLI      := $(BUILD)/largesteps

.PHONY: all lib check test run install bench bench-fit tradeoffs clean lint examples cross m4 size size-update digest-update FORCE
.DEFAULT_GOAL := all

ifeq ($(HOSTED),1)
all: $(LIB) $(CLI)
else
all: $(LIB)
endif
lib: $(LIB)

# config.h is rewritten only when its contents change, so switching REAL rebuilds
# everything and repeating a build rebuilds nothing.
$(CONFIG_H): FORCE
	@mkdir -p $(@D)
	@printf '%s\n' '/* Generated by make: the configuration this build of largesteps was made with. */' \
	  '#ifndef LARGESTEPS_CONFIG_H' '#define LARGESTEPS_CONFIG_H' \
	  '#define LS_REAL_IS_FLOAT $(REAL_IS_FLOAT)' '#define LS_SUMS_DOUBLE $(SUMS_DOUBLE)' '#endif' > $@.tmp
	@if cmp -s $@.tmp $@; then rm -f $@.tmp; else mv $@.tmp $@; fi

$(BUILD)/obj/src/%.o: %.c $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) $(CFLAGS_LIB) $(CALLGRAPH) -MMD -MP -c $< -o $@

$(BUILD)/obj/port/%.o: $(PORT_DIR)/%.c $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) $(CFLAGS_PORT) -MMD -MP -c $< -o $@

$(LIB): $(LIB_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

$(PORTLIB): $(PORT_OBJ)
	@rm -f $@
	$(AR) rcs $@ $^

# The bunny compiled into the program (the default target of `largesteps fit`),
# as a C array made with od and sed (no host tools beyond POSIX).
EMBED_C  := $(BUILD)/gen/embedded_bunny.c
$(EMBED_C): fixtures/meshes/bunny.obj
	@mkdir -p $(@D)
	@{ printf '%s\n' '/* generated by make from fixtures/meshes/bunny.obj */' '#include <stddef.h>' \
	  'extern const unsigned char ls_embedded_bunny_obj[];' 'extern const size_t ls_embedded_bunny_obj_size;' \
	  'const unsigned char ls_embedded_bunny_obj[] = {'; \
	  od -An -v -tx1 $< | sed -e 's/ *\([0-9a-f][0-9a-f]\)/0x\1,/g'; \
	  printf '%s\n' '};' 'const size_t ls_embedded_bunny_obj_size = sizeof ls_embedded_bunny_obj;'; } > $@.tmp
	@mv $@.tmp $@

$(CLI): port/posix/program/main.c $(EMBED_C) $(PORTLIB) $(LIB) $(CONFIG_H)
	$(CC) $(CFLAGS_PORT) $< $(EMBED_C) $(PORTLIB) $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

# The port's objects are linked as objects, not from the archive: on bare
# metal nothing references the vector table, which must be linked all the same.
ifeq ($(HOSTED),1)
PORT_LINK := $(PORTLIB)
else
PORT_LINK := $(PORT_OBJ)
endif

$(BUILD)/tests/%: tests/%.c tests/test.h $(PORT_LINK) $(LIB) $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) $(CFLAGS_TEST) -MMD -MP $< $(PORT_LINK) $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

# One variant: build, run every test program and the digest, then the checks
# on the built objects. Every step runs; the recipe fails if any failed.
check: all $(CHECK_BIN) $(DIGEST)
	@$(if $(CHECK_BIN),$(if $(CROSS_SKIP),echo "     not run under emulation (tests/tools/cross_skip.txt): $(CROSS_SKIP)";),echo "     the digest and the hygiene checks alone (DIGEST_ONLY=1)";) st=0; \
	$(if $(CHECK_BIN),sh tests/run_variant.sh "$(BUILD)" "$(RUNNER)" $(CHECK_BIN) || st=1;) \
	sh tests/tools/digest_check.sh "$(DIGEST)" "$(DIGEST_FIXTURE)" "$(RUNNER)" || st=1; \
	NM="$(NM)" SIZE="$(SIZE)" STACK_BUDGET=$(STACK_BUDGET) sh tests/hygiene.sh "$(BUILD)" "$(CC) $(ARCHFLAGS)" "$(CXX)" "$(SAN)" "$(CC_IS_GCC)" || st=1; \
	exit $$st

# The emulated targets and the Cortex-M4 port (also stages of `make test`).
cross:
	@sh tests/stage_cross.sh

m4:
	@sh tests/stage_cortex_m4.sh

size:
	@sh tests/tools/m4_size.sh

size-update:
	@sh tests/tools/m4_size.sh --update

# Rewrites the expected digests from this machine's gcc builds (both ls_real,
# and float with float sums: the Cortex-M4's configuration).
# Commit them with the change that moved them, after reading the diff.
digest-update:
	@for r in double float; do \
	  $(MAKE) --no-print-directory REAL=$$r BUILD=build/digest-$$r TARGET= build/digest-$$r/tests/digest >/dev/null && \
	  ./build/digest-$$r/tests/digest > fixtures/digest-$$r.txt && echo "wrote fixtures/digest-$$r.txt"; \
	done; \
	$(MAKE) --no-print-directory REAL=float SUMS=real BUILD=build/digest-float-floatsums TARGET= \
	  build/digest-float-floatsums/tests/digest >/dev/null && \
	./build/digest-float-floatsums/tests/digest > fixtures/digest-float-floatsums.txt && \
	echo "wrote fixtures/digest-float-floatsums.txt"

# The native matrix (gcc double, gcc float, clang double, ASan+UBSan), static
# analysis, the install checks, then the stages tests/stage_*.sh (the emulated
# targets, Cortex-M4, ...); each stage's time is checked against
# tests/tools/budgets.txt. The last line is "N passed, M failed".
test:
	@sh tests/tools/budget.sh

lint:
	@sh tests/lint.sh

# The example programs (examples/*.c), built as a user builds them; run by the
# stage tests/stage_examples.sh of `make test` against examples/*.expected.
EXAMPLE_BIN := $(patsubst examples/%.c,$(BUILD)/examples/%,$(sort $(wildcard examples/*.c)))
examples: $(EXAMPLE_BIN)

$(BUILD)/examples/%: examples/%.c $(LIB) $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) $(CFLAGS_TEST) $< $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

# The default reconstruction: the embedded bunny from an icosphere, 16 views
# at 128 x 128, 400 iterations, remeshed twice (about 30 s of one core);
# prints the stage times and the final metrics, writes $(BUILD)/run/.
run: $(CLI)
	@$(CLI) info
	@$(CLI) fit --quiet -o $(BUILD)/run

# The speed/accuracy study: the bunny and the elephant, every knob
# in double, the default configuration in float too; tables and plot in
# $(BUILD)/tradeoffs/ (TRADEOFFS_ARGS, e.g. --iters 200, scales it down);
# then the Cortex-M4 study under QEMU (instruction counts, m4-*.md).
TRADEOFFS_ARGS ?=
TRADE_DIR := $(BUILD)/tradeoffs
tradeoffs: $(CLI)
	@$(MAKE) --no-print-directory REAL=float BUILD=$(BUILD)/float $(BUILD)/float/largesteps
	@mkdir -p $(TRADE_DIR)
	$(BUILD)/float/largesteps experiment tradeoffs --knobs none $(TRADEOFFS_ARGS) --rows-out $(TRADE_DIR)/float-bunny.tsv -o $(TRADE_DIR)/float-bunny
	$(BUILD)/float/largesteps experiment tradeoffs fixtures/meshes/elephant.obj --knobs none $(TRADEOFFS_ARGS) --rows-out $(TRADE_DIR)/float-elephant.tsv -o $(TRADE_DIR)/float-elephant
	$(CLI) experiment tradeoffs fixtures/meshes/elephant.obj $(TRADEOFFS_ARGS) --rows-out $(TRADE_DIR)/double-elephant.tsv -o $(TRADE_DIR)/elephant
	$(CLI) experiment tradeoffs $(TRADEOFFS_ARGS) --rows-in $(TRADE_DIR)/float-bunny.tsv --rows-in $(TRADE_DIR)/float-elephant.tsv --rows-in $(TRADE_DIR)/double-elephant.tsv -o $(TRADE_DIR)
	@for real in float double; do \
	    $(MAKE) --no-print-directory TARGET=cortex-m4 PROFILE=full REAL=$$real BUILD=build/cortex-m4-full-$$real \
	        build/cortex-m4-full-$$real/bench/m4_tradeoffs > /dev/null || exit 1; \
	    LS_M4_ICOUNT=1 LS_M4_TIMEOUT=1200 sh tests/tools/run_m4.sh build/cortex-m4-full-$$real/bench/m4_tradeoffs \
	        > $(TRADE_DIR)/m4-$$real.md || exit 1; cat $(TRADE_DIR)/m4-$$real.md; \
	done

# Benchmarks against peers measured in the same run (bench-only packages:
# libsuitesparse-dev libeigen3-dev libosmesa6-dev libcgal-dev libfftw3-dev); tables in $(BUILD)/bench/.
bench: all $(BUILD)/bench/bench_gradient
	@mkdir -p $(BUILD)/bench
	BENCH_OUT=$(BUILD)/bench/gradient.md $(BUILD)/bench/bench_gradient
	@# the same table with ls_real = float (the precision knob)
	$(if $(filter double,$(REAL)),$(MAKE) --no-print-directory REAL=float BUILD=$(BUILD)/float $(BUILD)/float/bench/bench_gradient && \
	  BENCH_OUT=$(BUILD)/bench/gradient_float.md $(BUILD)/float/bench/bench_gradient,@true)
	BUILD=$(BUILD) sh tests/bench/run_ldlt.sh
	BUILD=$(BUILD) sh tests/bench/run_param.sh
	BUILD=$(BUILD) sh tests/bench/run_split.sh
	BUILD=$(BUILD) sh tests/bench/run_grid.sh
	BUILD=$(BUILD) REAL=$(REAL) sh tests/tools/bench_render.sh
	BUILD=$(BUILD) sh tests/bench/run_refine.sh
	BUILD=$(BUILD) sh tests/bench/run_distance.sh
	BUILD=$(BUILD) sh tests/bench/run_fan.sh
	BUILD=$(BUILD) sh tests/bench/run_dataset.sh
	BUILD=$(BUILD) sh tests/bench/run_remesh.sh
	BUILD=$(BUILD) sh tests/bench/run_fit.sh
	BUILD=$(BUILD) sh tests/bench/run_workers.sh
	BUILD=$(BUILD) sh tests/bench/run_scaling.sh
	BUILD=$(BUILD) REAL=$(REAL) sh tests/bench/fast_paths.sh


# The fit suite (tests/bench/fit_suite.txt): `largesteps fit` with default
# options on every target and 5 runs each with the learning rate moved in the
# 6th digit; table in $(BUILD)/bench/fit_suite.md. Bench-only packages:
# libcgal-demo (CGAL's meshes) and time (GNU time: peak memory); about 25
# minutes on two cores.
bench-fit: all
	BUILD=$(BUILD) sh tests/bench/fit_suite.sh

# Every benchmark program tests/bench/NAME.c is built by this one rule as
# $(BUILD)/bench/NAME (the scripts in tests/bench/ and `make bench` ask for
# them by name): bench_silhouette MESH TARGET RES VIEWS REPEAT, bench_refine
# MESH [RES [VIEWS [REPS]]], bench_loss [RES [VIEWS [REPEAT]]], bench_gradient
# (table in $(BUILD)/bench/gradient.md), bench_ldlt, bench_param, bench_grid,
# bench_distance, bench_remesh; m4_tradeoffs with TARGET=cortex-m4 (`make
# tradeoffs` runs it under QEMU with -icount).
$(BUILD)/bench/%: tests/bench/%.c $(PORT_LINK) $(LIB) $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) $(CFLAGS_TEST) -I$(PORT_DIR) $< $(PORT_LINK) $(LIB) $(LDFLAGS) $(LDLIBS) -o $@

# The peers the benchmarks measure against, from the bench-only packages.
$(BUILD)/bench/peer_cholmod: tests/bench/peer_cholmod.c
	@mkdir -p $(@D)
	$(CC) -O2 -std=c99 -I/usr/include/suitesparse $< -lcholmod -lm -o $@
$(BUILD)/bench/peer_eigen: tests/bench/peer_eigen.cpp
	@mkdir -p $(@D)
	$(CXX) -O2 -I/usr/include/eigen3 -Itests/bench $< -o $@
$(BUILD)/bench/peer_fftw_grid: tests/bench/peer_fftw_grid.c $(LIB) $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -ffp-contract=off -Wall -Wextra -Werror $(INCLUDES) $< $(LIB) -lfftw3 -lm -o $@
$(BUILD)/bench/peer_cgal_distance: tests/bench/peer_cgal_distance.cpp
	@mkdir -p $(@D)
	$(CXX) -O2 -DNDEBUG $< -o $@
$(BUILD)/bench/cgal_remesh: tests/peers/cgal_remesh.cpp
	@mkdir -p $(@D)
	$(CXX) -O2 -std=c++17 $< -lgmp -lmpfr -o $@
$(BUILD)/bench/osmesa_bench: tests/tools/osmesa_peer.c $(LIB) $(CONFIG_H)
	@mkdir -p $(@D)
	$(CC) -std=c99 -D_POSIX_C_SOURCE=200809L -O2 -Wall -Wextra -Werror $(INCLUDES) $< $(LIB) -lOSMesa -lGLU -lm -o $@

install: $(LIB) $(CONFIG_H)
	@mkdir -p $(DESTDIR)$(PREFIX)/lib/pkgconfig $(DESTDIR)$(PREFIX)/include/$(VARIANT_NAME)/largesteps
	cp $(LIB) $(DESTDIR)$(PREFIX)/lib/lib$(VARIANT_NAME).a
	cp include/largesteps.h $(DESTDIR)$(PREFIX)/include/$(VARIANT_NAME)/
	cp include/largesteps/*.h $(CONFIG_H) $(DESTDIR)$(PREFIX)/include/$(VARIANT_NAME)/largesteps/
	@printf '%s\n' 'prefix=$(PREFIX)' 'libdir=$${prefix}/lib' 'includedir=$${prefix}/include/$(VARIANT_NAME)' '' \
	  'Name: $(VARIANT_NAME)' \
	  'Description: largesteps inverse rendering library (ls_real = $(REAL))' \
	  'Version: '"$$(sed -n 's/^#define LS_VERSION_STRING "\(.*\)"/\1/p' include/largesteps/core.h)" \
	  'Cflags: -I$${includedir}' 'Libs: -L$${libdir} -l$(VARIANT_NAME) -lm' \
	  > $(DESTDIR)$(PREFIX)/lib/pkgconfig/$(VARIANT_NAME).pc
	@echo "installed $(VARIANT_NAME) into $(DESTDIR)$(PREFIX)"

# --- hardening: fuzzing (tests/fuzz/) and valgrind --------------------------
# libFuzzer targets, one per decoder of untrusted bytes, built with clang
# against a copy of the library instrumented for coverage, with ASan and
# UBSan (float-cast-overflow included, every report fatal); Debian packages
# clang and libclang-rt-14-dev (the fuzzer runtime).
#   make fuzz          each target fuzzes for FUZZ_TIME seconds (default 60)
#                      after replaying its corpus tests/fuzz/corpus/NAME/
#   make fuzz-replay   the same for at most 10 s per target (the stage
#                      tests/stage_fuzz.sh of `make test`)
#   make fuzz-build    only build them ($(FUZZ_BUILD)/fuzz_NAME)
#   make valgrind      the stage tests/stage_valgrind.sh (a subset of the
#                      unit tests under valgrind --leak-check=full)
# New inputs found go to $(FUZZ_BUILD)/work/NAME/, never into the repository.
FUZZ_TARGETS := obj ply off png ppm pfm scene mitsuba transforms
FUZZ_BUILD   ?= build/fuzz
FUZZ_TIME    ?= 60
FUZZ_CC      ?= clang
FUZZ_CFLAGS  := -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wvla -g -O1 -fno-omit-frame-pointer \
                -ffp-contract=off -fsanitize=fuzzer,address,undefined,float-cast-overflow \
                -fno-sanitize-recover=all -Iinclude -I$(FUZZ_BUILD)/include -Itests/fuzz
FUZZ_BINS    := $(FUZZ_TARGETS:%=$(FUZZ_BUILD)/fuzz_%)

.PHONY: fuzz fuzz-build fuzz-replay valgrind
fuzz-build:
	@$(MAKE) --no-print-directory CC=$(FUZZ_CC) SAN=1 REAL=double TARGET= BUILD=$(FUZZ_BUILD) \
	  ARCHFLAGS=-fsanitize=fuzzer-no-link $(FUZZ_BUILD)/liblargesteps.a
	@$(MAKE) --no-print-directory FUZZ_BUILD=$(FUZZ_BUILD) FUZZ_CC=$(FUZZ_CC) $(FUZZ_BINS)

$(FUZZ_BUILD)/fuzz_%: tests/fuzz/fuzz_%.c $(wildcard tests/fuzz/*.h) $(FUZZ_BUILD)/liblargesteps.a
	$(FUZZ_CC) $(FUZZ_CFLAGS) $< $(FUZZ_BUILD)/liblargesteps.a -lz -lm -o $@

fuzz:
	@FUZZ_TIME=$(FUZZ_TIME) FUZZ_BUILD=$(FUZZ_BUILD) sh tests/stage_fuzz.sh

fuzz-replay:
	@FUZZ_TIME=10 FUZZ_BUILD=$(FUZZ_BUILD) sh tests/stage_fuzz.sh

valgrind:
	@sh tests/stage_valgrind.sh

clean:
	rm -rf build

FORCE:

-include $(LIB_OBJ:.o=.d) $(PORT_OBJ:.o=.d) $(TEST_BIN:=.d) $(DIGEST).d
