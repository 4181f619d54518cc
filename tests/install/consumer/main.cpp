// Smallest user program: link semfuse::client from an installed semfuse. Without arguments it
// prints the library version (what the install test runs); with --status it waits up to 5 s for
// a server's status on the default domain, which links the DDS side of the library too.
#include <chrono>
#include <cstdio>
#include <string>

#include <semfuse/client/map_client.hpp>
#include <semfuse/client/version.hpp>
#include <semfuse/dds/participant.hpp>

int main(int argc, char** argv) {
  std::printf("semfuse client %s\n", semfuse::client::version());
  if (argc < 2 || std::string(argv[1]) != "--status") return 0;
  semfuse::dds::Participant participant;
  semfuse::client::MapClient map(participant);
  const auto status = map.waitForStatus(std::chrono::seconds(5));
  if (!status) {
    std::printf("no server status within 5 s\n");
    return 4;
  }
  std::printf("server %s: %llu frames integrated\n", status->server_id.c_str(),
              static_cast<unsigned long long>(status->frames_integrated));
  return 0;
}
