// `glcast keygen DIR/NAME`: a CURVE key pair for a wall (docs/security.md, "Keys").
#include <cstdio>

#include "cli/commands.h"
#include "net/security.h"

namespace glcast::cli {

Command add_keygen(CLI::App& glcast) {
    auto path = std::make_shared<std::string>();
    CLI::App* app = glcast.add_subcommand("keygen", "make a CURVE key pair: PATH.key (secret, mode 0600) and PATH.pub");
    app->footer("A wall's keys folder holds master.pub everywhere, master.key on the machine that runs programs,\n"
                "slave.key on each display machine, and on the master authorized/NAME.pub for each display\n"
                "machine it serves. Name it with --keys DIR, the display config's \"keys\" or GLCAST_KEYS.");
    app->add_option("PATH", *path, "DIR/NAME: where to write NAME.key and NAME.pub (never overwritten)")->required();
    return {app, [path](const std::vector<std::string>&) {
                std::string error;
                if (!net::write_key_pair(*path, error)) {
                    std::fprintf(stderr, "glcast keygen: %s\n", error.c_str());
                    return 1;
                }
                net::KeyPair k;
                if (!net::read_key_file(*path + ".pub", false, k, error)) {
                    std::fprintf(stderr, "glcast keygen: %s\n", error.c_str());
                    return 1;
                }
                std::printf("%s.key and %s.pub: public key %s\n", path->c_str(), path->c_str(), k.public_key.c_str());
                return 0;
            }};
}

}  // namespace glcast::cli
