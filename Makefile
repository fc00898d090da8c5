# The two commands of the README. Both install what is missing from Debian 12, then build.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
# What building and running the command line needs (make demo), then what the tests, the Python
# module, the docs and the browser test add (make test).
CLI_PACKAGES = build-essential cmake pkg-config libopenimageio-dev openimageio-tools \
    libopenexr-dev libopencolorio-dev libembree-dev libtbb-dev libcli11-dev nlohmann-json3-dev \
    doctest-dev libfmt-dev libhwy-dev libtinygltf-dev libtinyobjloader-dev fonts-dejavu-core \
    libcpp-httplib-dev
DEBIAN_PACKAGES = $(CLI_PACKAGES) chromium python3 python3-jsonschema help2man zsh fish graphviz \
    pybind11-dev libdlpack-dev python3-dev python3-numpy python3-pytest python3-venv python3-pip \
    python3-setuptools python3-wheel mypy python3-torch
FRAMEPASS = $(BUILD_DIR)/cli/framepass
# A recipe line piped through grep fails when framepass fails, not only when grep does.
SHELL := /bin/bash
.SHELLFLAGS := -o pipefail -c
# Extra cmake arguments, e.g. CMAKE_ARGS=-DFP_WERROR=ON (CI: every warning of gcc and clang is an error).
CMAKE_ARGS ?=
# The CUDA backend: built where nvcc is found and a GPU answers nvidia-smi (auto), or always (on:
# to carry the GPU check to another machine, docs/gpu.md), or never (off). Its kernels are a third
# of a fresh build's time, useless without a GPU.
CUDA ?= auto
ifeq ($(CUDA),auto)
FP_CUDA := $(shell nvidia-smi -L >/dev/null 2>&1 && echo ON || echo OFF)
else ifeq ($(CUDA),on)
FP_CUDA := ON
else
FP_CUDA := OFF
endif
# make fuzz: the libFuzzer targets of fuzz/ under ASan + UBSan, each run FUZZ_SECONDS from its
# seed corpus with a fixed seed (so CI's short run is the start of a long local one).
FUZZ_PACKAGES = clang libclang-rt-14-dev
FUZZ_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_TARGETS = ConfigFuzz CaptureFuzz SidecarFuzz ObjFuzz GltfFuzz ServeRequestFuzz

.PHONY: demo results test deps deps-cli build build-cli fuzz bench bench-sequence stability

# Installs what is missing of the packages $(1) (as root; otherwise prints the apt-get line).
define install_missing
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "Installing Debian packages:" $$missing; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; \
	  else \
	    echo "framepass needs these Debian packages. Run:"; \
	    echo "  sudo apt-get install -y" $$missing; exit 1; \
	  fi; \
	fi
endef

deps-cli:
	$(call install_missing,$(CLI_PACKAGES))

deps:
	$(call install_missing,$(DEBIAN_PACKAGES))
	@# node and npm, for the workbench's browser test (Playwright): Debian's, unless a node is there.
	@command -v npm >/dev/null || { \
	  if [ "$$(id -u)" = 0 ]; then apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm; \
	  else echo "framepass's browser test needs node: sudo apt-get install -y nodejs npm"; exit 1; fi; }

build: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DFP_CUDA=$(FP_CUDA) $(CMAKE_ARGS)
	cmake --build $(BUILD_DIR) -j $(JOBS)

# The command line alone (no test suite, Python module or GPU check): what make demo runs.
build-cli: deps-cli
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DFP_CUDA=$(FP_CUDA) $(CMAKE_ARGS)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target framepass

demo: build-cli
	rm -rf out/demo
	$(FRAMEPASS) capture examples/cornell/scene.json -o out/demo/cornell.exr --truth
	$(FRAMEPASS) sheet out/demo/cornell.exr -o out/demo/capture_sheet.png
	$(FRAMEPASS) plan examples/cornell/config.json
	$(FRAMEPASS) run examples/cornell/config.json -o out/demo --report out/demo/report.json
	$(FRAMEPASS) compare out/demo/cornell.exr out/demo/cornell.exr --layer Truth.DiffuseIndirectOneBounce \
	    --ref-layer Truth.DiffuseIndirectFull --heatmap out/demo/one_bounce_error.exr
	$(FRAMEPASS) bench examples/cornell/bench.json --runs 1 --sweep r.SSGI.Quality=1..4 \
	    --html out/demo/bench.html | grep -v '^Progress'
	$(FRAMEPASS) tune examples/cornell/bench.json --target 'ssgi_vs_one_bounce<=0.035' \
	    --sweep r.SSGI.Quality=1..4 --sweep r.SSGI.HalfRes=0,1 --runs 1 | grep -v '^Progress'
	@echo "framepass wrote:"; find out/demo -type f | sort | sed 's/^/  /'
	@echo "The look-dev workbench on this capture (docs/serve.md):"
	@echo "  $(FRAMEPASS) serve examples/cornell/bench.json --open"
	@echo "The rest of the captures and benches behind docs/results/: make results"

# make results: make demo, then the captures and benches behind docs/results/ (ssgi, shadows,
# reflections, beyond) into out/demo/: a 4-frame sequence, the oracle, the shadows, the glossy room
# and the hard scene, and the ray-traced passes and the hybrid against SSGI on all three captures.
results: demo
	$(FRAMEPASS) capture examples/cornell/scene.json -o 'out/demo/seq/cornell.####.exr' --frames 1-4 \
	    --truth --truth-spp 64 | grep -v '^ '
	$(FRAMEPASS) bench examples/cornell/bench.json --capture 'out/demo/seq/cornell.####.exr' --frames 1-4 \
	    --runs 1 --decompose-rays 0 --sweep r.DiffuseIndirect.Denoiser=0,1 --html out/demo/sequence.html \
	    | grep -v '^Progress'
	$(FRAMEPASS) bench examples/cornell/oracle.json --runs 1 --sweep screen_space_oracle.rays=4,16,64 \
	    | grep -v '^Progress'
	$(FRAMEPASS) bench examples/cornell/shadows.json --runs 3 --sweep r.RayTracing.Shadow.SamplesPerPixel=1,4 \
	    --sweep r.Shadow.Denoiser=0,2 --html out/demo/shadows.html | grep -v '^Progress'
	$(FRAMEPASS) capture examples/glossy/scene.json -o out/demo/glossy/glossy.exr --truth | grep -v '^ '
	$(FRAMEPASS) bench examples/glossy/bench.json --capture out/demo/glossy/glossy.exr --runs 3 \
	    --sweep r.SSR.Quality=0..4 --set ssr.postProcessQuality=100 --html out/demo/glossy.html | grep -v '^Progress'
	$(FRAMEPASS) bench examples/cornell/beyond.json --runs 1 --html out/demo/beyond.html | grep -v '^Progress'
	$(FRAMEPASS) bench examples/glossy/beyond.json --runs 1 --html out/demo/beyond_glossy.html | grep -v '^Progress'
	$(FRAMEPASS) capture examples/hard/scene.json -o out/demo/hard/hard.exr --truth | grep -v '^ '
	$(FRAMEPASS) bench examples/hard/beyond.json --runs 1 --html out/demo/beyond_hard.html | grep -v '^Progress'
	@echo "framepass wrote:"; find out/demo -type f | sort | sed 's/^/  /'

# ctest reports a suite that cannot run here (no Slurm, no GPU, no Chromium) as skipped; ctest.xml
# (JUnit) lists what ran and what skipped, for .ci/run.
test: build
	cd $(BUILD_DIR) && ctest --output-on-failure --output-junit ctest.xml

# make bench: the 1080p speed table of docs/results/speed-1080p.md (captures out/bench/ once; BENCH_RUNS timed runs).
BENCH_RUNS ?= 3
bench: build
	python3 examples/bench/bench_1080p.py --framepass $(FRAMEPASS) --runs $(BENCH_RUNS)

# make bench-sequence: the shot of docs/results/sequence.md (a 1080p glossy capture of SEQUENCE_FRAMES, run
# end to end with and without the pipeline, every pass at 2 threads and at all; --device cuda too where a GPU answers).
SEQUENCE_FRAMES ?= 1-12
bench-sequence: build
	bash examples/bench/sequence_bench.sh $(FRAMEPASS) out/sequence $(SEQUENCE_FRAMES)

# make stability: the half-float table of docs/results/half-float.md (captures into out/stability/ and compares every
# pass output of half captures with the float32 capture's).
stability: build
	python3 examples/stability/half_float.py --framepass $(FRAMEPASS)

fuzz: deps
	@missing=$$(for p in $(FUZZ_PACKAGES); do dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; fi
	cmake -S . -B $(FUZZ_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DFP_FUZZ=ON $(CMAKE_ARGS)
	cmake --build $(FUZZ_DIR) -j $(JOBS) --target $(FUZZ_TARGETS) SessionRace
	@# A session raced from threads under the same sanitizers (fuzz/SessionRace.cpp).
	$(FUZZ_DIR)/fuzz/SessionRace $(CURDIR) $(FUZZ_DIR)/race $(FUZZ_SECONDS)
	@for t in $(FUZZ_TARGETS); do \
	  seeds=fuzz/corpus/$$(echo $$t | sed 's/Fuzz$$//' | tr A-Z a-z); \
	  mkdir -p $(FUZZ_DIR)/corpus/$$t $(FUZZ_DIR)/findings; \
	  echo "fuzzing $$t for $(FUZZ_SECONDS) s (seeds: $$seeds)"; \
	  $(FUZZ_DIR)/fuzz/$$t -seed=1 -max_total_time=$(FUZZ_SECONDS) -timeout=20 -rss_limit_mb=4096 \
	    -max_len=65536 -artifact_prefix=$(FUZZ_DIR)/findings/$$t- -print_final_stats=1 \
	    $(FUZZ_DIR)/corpus/$$t $$seeds 2> $(FUZZ_DIR)/$$t.log || { tail -40 $(FUZZ_DIR)/$$t.log; exit 1; }; \
	  grep -E "stat::number_of_executed_units|Done [0-9]+ runs" $(FUZZ_DIR)/$$t.log | tail -2; \
	done
