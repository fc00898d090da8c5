#include "tests/support/TestScenes.h"

#include "io/ConfigLoader.h"

namespace fp::test {

// The shipped OCIO config ($FRAMEPASS_CONFIG_DIR overrides where it is).
OCIO_NAMESPACE::ConstConfigRcPtr MemorySource::colorConfig() {
    return OCIO_NAMESPACE::Config::CreateFromFile(
        (io::configDirectory() + "/ocio/config.ocio").c_str());
}

}  // namespace fp::test
