// Smallest user program: link semfuse::client from an installed semfuse.
#include <cstdio>

#include <semfuse/client/version.hpp>

int main() {
  std::printf("semfuse client %s\n", semfuse::client::version());
  return 0;
}
