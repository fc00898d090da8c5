// framepass schema: the JSON Schema of a config or a scene, from the shapes the readers check
// (io/JsonShape.h). docs/schema/ holds them; an editor validates and completes with them.
#include "cli/Commands.h"
#include "io/JsonShape.h"

#include <iostream>

namespace fp::cli {

Command addSchemaCommand(CLI::App& app) {
    auto document = std::make_shared<std::string>();
    CLI::App* sub = app.add_subcommand(
        "schema", "print the JSON Schema of a config or a scene (for editors: \"$schema\")");
    sub->add_option("document", *document, "config or scene")->required();
    return [document]() {
        std::cout << io::documentShape(*document).jsonSchema().dump(2) << "\n";
        return 0;
    };
}

}  // namespace fp::cli
