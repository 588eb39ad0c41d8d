#include "cli_server.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>
#include <stdexcept>

#include "cli.h"

namespace fluidtex::test {

namespace {

int server_socket = -1;  // the tests' end of the socket pair
bool command_running = false;
std::mutex server_mutex;

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n, size -= static_cast<std::size_t>(n);
  }
  return true;
}

bool read_all(int fd, void* data, std::size_t size) {
  char* p = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t n = ::read(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n, size -= static_cast<std::size_t>(n);
  }
  return true;
}

/// A request: the setup's fields then the arguments, each string as its
/// length (4 bytes) and bytes.
void put(std::string& out, const std::string& s) {
  const auto n = static_cast<std::uint32_t>(s.size());
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  out += s;
}

std::string get(const std::string& in, std::size_t& at) {
  std::uint32_t n = 0;
  if (at + sizeof n > in.size()) std::_Exit(125);
  std::memcpy(&n, in.data() + at, sizeof n);
  at += sizeof n;
  if (at + n > in.size()) std::_Exit(125);
  std::string s = in.substr(at, n);
  at += n;
  return s;
}

/// In the forked copy: the command, as the executable would run it.
[[noreturn]] void run_command(const std::string& request) {
  std::size_t at = 0;
  const std::string executable = get(request, at);
  const std::string cwd = get(request, at), out = get(request, at), err = get(request, at);
  const std::uint64_t memory = std::stoull(get(request, at));
  const unsigned cpu = static_cast<unsigned>(std::stoul(get(request, at)));
  std::vector<std::string> args{executable.empty() ? "fluidtex" : executable};
  while (at < request.size()) args.push_back(get(request, at));
  if (::chdir(cwd.c_str()) != 0) std::_Exit(126);
  if (memory > 0) {
    const rlimit limit{memory, memory};
    ::setrlimit(RLIMIT_AS, &limit);
  }
  const rlimit cpu_limit{cpu, cpu};
  ::setrlimit(RLIMIT_CPU, &cpu_limit);
  const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (o < 0 || e < 0) std::_Exit(126);
  ::dup2(o, 1), ::dup2(e, 2);
  ::close(o), ::close(e);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  if (!executable.empty()) {
    ::execv(executable.c_str(), argv.data());
    std::_Exit(127);
  }
  // Streams flushed, then _exit without static destructors: some libraries'
  // destructors (log4cplus, through OpenVDB) join threads that the test
  // binary started before the fork and that this process does not have, and
  // would wait forever. The command's outputs are renamed into place before
  // it returns, so nothing it writes depends on them.
  const int code = cli::run_command_line(static_cast<int>(args.size()), argv.data());
  std::cout.flush(), std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(code);
}

/// The server: one command at a time, until the tests' end closes.
[[noreturn]] void serve(int socket) {
  for (;;) {
    std::uint32_t size = 0;
    if (!read_all(socket, &size, sizeof size)) std::_Exit(0);
    std::string request(size, '\0');
    if (!read_all(socket, request.data(), size)) std::_Exit(0);
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::close(socket);
      run_command(request);
    }
    const std::int32_t sent = pid;
    if (!write_all(socket, &sent, sizeof sent)) std::_Exit(0);
    if (pid < 0) continue;
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    const std::int32_t result = status;
    if (!write_all(socket, &result, sizeof result)) std::_Exit(0);
  }
}

}  // namespace

void start_cli_server() {
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return;
  std::fflush(nullptr);
  std::cout.flush(), std::cerr.flush();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    serve(fds[1]);
  }
  ::close(fds[1]);
  if (pid < 0) {
    ::close(fds[0]);
    return;
  }
  server_socket = fds[0];
}

Command spawn_command_line(const std::vector<std::string>& args, const CommandSetup& setup) {
  const std::lock_guard lock(server_mutex);
  if (server_socket < 0) throw std::runtime_error("the command-line server is not running (start_cli_server)");
  if (command_running) throw std::runtime_error("spawn_command_line: the previous command was not waited for");
  std::string request;
  put(request, setup.executable.string());
  put(request, setup.cwd.string());
  put(request, setup.stdout_file.string());
  put(request, setup.stderr_file.string());
  put(request, std::to_string(setup.memory_limit));
  put(request, std::to_string(setup.cpu_seconds));
  for (const std::string& a : args) put(request, a);
  const auto size = static_cast<std::uint32_t>(request.size());
  std::int32_t pid = -1;
  if (!write_all(server_socket, &size, sizeof size) || !write_all(server_socket, request.data(), size) ||
      !read_all(server_socket, &pid, sizeof pid))
    throw std::runtime_error("the command-line server went away");
  if (pid < 0) throw std::runtime_error("the command-line server could not fork");
  command_running = true;
  return Command{pid};
}

bool wait_command_line(const Command& command, double seconds, int& status) {
  const std::lock_guard lock(server_mutex);
  if (!command_running || command.pid < 0) throw std::runtime_error("wait_command_line: no command running");
  pollfd p{server_socket, POLLIN, 0};
  int ready;
  while ((ready = ::poll(&p, 1, static_cast<int>(seconds * 1000.0))) < 0 && errno == EINTR) {
  }
  if (ready == 0) return false;
  std::int32_t result = 0;
  if (!read_all(server_socket, &result, sizeof result)) throw std::runtime_error("the command-line server went away");
  command_running = false;
  status = result;
  return true;
}

}  // namespace fluidtex::test
