// Connects to a domain through the installed lpss client library; finds no cluster, as expected.
#include <cstdio>

#include "lpss/client/client.hpp"

int main() {
    lpss::ClientOptions options;
    options.domain = 141;  // a domain no other test uses: it must find no cluster
    options.name = "package-user";
    auto client = lpss::Client::connect(options);
    if (!client) return 1;
    std::printf("connected; cluster: %s\n",
                (*client)->wait_for_cluster(std::chrono::milliseconds(200)) ? "yes" : "no");
    return 0;
}
