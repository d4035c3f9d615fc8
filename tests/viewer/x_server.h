// An Xvfb of the test's own, for the viewer runs of one test.
//
// Why not xvfb-run per viewer run: its clean-up removes its temporary directory before it stops
// the server, and now and then that `rm -r` fails; it then exits 5 in place of the viewer's exit
// code (seen in CI: a viewer that exited 1 read as 5). Here the server is started once with
// -displayfd, so it picks a free display itself (no race between servers) and writes the number
// once it accepts connections; the destructor stops it and waits for it.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <memory>
#include <string>

namespace firelook::testing {

class XServer {
  public:
    // Starts Xvfb; nullptr if it is not installed or does not come up (its error is then in
    // `log`, which is also where the server's own messages go).
    static std::unique_ptr<XServer> start(const std::string& log) {
        int fds[2];
        if (pipe(fds) != 0) return nullptr;
        const pid_t pid = fork();
        if (pid < 0) {
            close(fds[0]);
            close(fds[1]);
            return nullptr;
        }
        if (pid == 0) {
            close(fds[0]);
            const int log_fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (log_fd >= 0) dup2(log_fd, STDERR_FILENO);
            const std::string fd = std::to_string(fds[1]);
            execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x800x24", "-nolisten", "tcp",
                   static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        std::string number;
        char c = 0;
        while (read(fds[0], &c, 1) == 1 && c != '\n') number += c;
        close(fds[0]);
        std::unique_ptr<XServer> server(new XServer(pid));
        if (number.empty()) return nullptr;  // exited before it took a display; the destructor reaps it
        server->display_ = ":" + number;
        return server;
    }

    ~XServer() {
        kill(pid_, SIGTERM);
        int status = 0;
        waitpid(pid_, &status, 0);
    }
    XServer(const XServer&) = delete;
    XServer& operator=(const XServer&) = delete;

    const std::string& display() const { return display_; }

  private:
    explicit XServer(pid_t pid) : pid_(pid) {}
    pid_t pid_;
    std::string display_;
};

}  // namespace firelook::testing
