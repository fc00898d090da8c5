# The two commands of the README. Both install what is missing from Debian 12, then build.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
DEBIAN_PACKAGES = build-essential cmake pkg-config libopenimageio-dev openimageio-tools \
    libopenexr-dev libopencolorio-dev libembree-dev libtbb-dev libcli11-dev nlohmann-json3-dev \
    doctest-dev libfmt-dev libtinygltf-dev libtinyobjloader-dev fonts-dejavu-core chromium python3
FRAMEPASS = $(BUILD_DIR)/cli/framepass

.PHONY: demo test deps build

deps:
	@missing=$$(for p in $(DEBIAN_PACKAGES); do dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "Installing Debian packages:" $$missing; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; \
	  else \
	    echo "framepass needs these Debian packages. Run:"; \
	    echo "  sudo apt-get install -y" $$missing; exit 1; \
	  fi; \
	fi

build: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD_DIR) -j $(JOBS)

demo: build
	rm -rf out/demo
	$(FRAMEPASS) capture examples/cornell/scene.json -o out/demo/cornell.exr --truth
	$(FRAMEPASS) sheet out/demo/cornell.exr -o out/demo/capture_sheet.png
	$(FRAMEPASS) plan examples/cornell/config.json
	$(FRAMEPASS) run examples/cornell/config.json -o out/demo --report out/demo/report.json
	$(FRAMEPASS) compare out/demo/cornell.exr out/demo/cornell.exr --layer Truth.DiffuseIndirectOneBounce \
	    --ref-layer Truth.DiffuseIndirectFull --heatmap out/demo/one_bounce_error.exr
	$(FRAMEPASS) bench examples/cornell/bench.json --runs 3 --sweep r.SSGI.Quality=1..4 \
	    --html out/demo/bench.html | grep -v '^Progress'
	$(FRAMEPASS) bench examples/cornell/shadows.json --runs 3 --sweep r.RayTracing.Shadow.SamplesPerPixel=1,4 \
	    --sweep r.Shadow.Denoiser=0,2 --html out/demo/shadows.html | grep -v '^Progress'
	@echo "framepass wrote:"; find out/demo -type f | sort | sed 's/^/  /'

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure
