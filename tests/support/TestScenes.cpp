#include "tests/support/TestScenes.h"

#include "io/CaptureSource.h"

namespace fp::test {

OCIO_NAMESPACE::ConstConfigRcPtr MemorySource::colorConfig() { return io::loadColorConfig(""); }

}  // namespace fp::test
