// A real PostgreSQL 15 cluster (Debian's postgresql-15) in a temp folder, on a free loopback
// port, for the postgres sink's tests: initdb'd, run as the test's child and removed with it.
// As root it runs as the `postgres` user; otherwise as the test's own.
#pragma once

#include <fcntl.h>
#include <libpq-fe.h>
#include <pwd.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "ls5_driver/cli_process.hpp"
#include "sinks/victoria_metrics.hpp"

namespace sinks_test {

inline constexpr const char* postgres_bin = "/usr/lib/postgresql/15/bin/";
inline constexpr const char* postgres_server = "/usr/lib/postgresql/15/bin/postgres";

struct PostgresCluster {
  ls5_driver_test::TempDir dir;
  std::uint16_t port = free_port();
  bool running = false;
  pid_t server = -1;    // the postmaster, a child of the test
  std::string failure;  // why set-up failed, for the test's message

  // `durable`: fsync on, as a plant's server (the bench); the tests run without it.
  explicit PostgresCluster(bool durable = false) : durable_(durable) {
    if (::geteuid() == 0) {
      // The server refuses to run as root: the folder is the postgres user's.
      const passwd* user = ::getpwnam("postgres");
      if (user == nullptr || ::chown(dir.path.c_str(), user->pw_uid, user->pw_gid) != 0) {
        failure = "no postgres user to run the cluster as";
        return;
      }
    }
    if (!run({"initdb", "-D", data(), "-A", "trust", "-U", "postgres", "-E", "UTF8", "--no-sync"})) {
      failure = "initdb failed: " + ls5_driver_test::read_file(dir.path / "command.log");
      return;
    }
    if (!start()) return;
    // The sink's login: a role with a password, owner of its database (so it may create tables).
    if (!admin("postgres", "CREATE ROLE rangekit LOGIN PASSWORD 'secret'") ||
        !admin("postgres", "CREATE DATABASE plant OWNER rangekit")) {
      failure = "could not make the role and database";
    }
  }
  ~PostgresCluster() { stop(); }
  PostgresCluster(const PostgresCluster&) = delete;
  PostgresCluster& operator=(const PostgresCluster&) = delete;

  [[nodiscard]] bool ready() const { return running && failure.empty(); }
  [[nodiscard]] std::string data() const { return (dir.path / "data").string(); }
  [[nodiscard]] std::string url() const { return "postgresql://rangekit@127.0.0.1:" + std::to_string(port) + "/plant"; }

  // The server itself as the test's child (not pg_ctl's), so that a test killed or crashed
  // takes it along; ready once it answers a login.
  bool start() {
    const pid_t test = ::getpid();
    server = rangekit::test::fork_child();
    if (server == 0) {
      const int log = ::open((dir.path / "server.log").c_str(), O_WRONLY | O_CREAT | O_APPEND, 0666);
      ::dup2(log, 1);
      ::dup2(log, 2);
      ::chdir(dir.path.c_str());
      if (::geteuid() == 0) {
        const passwd* user = ::getpwnam("postgres");
        if (user == nullptr || ::setgid(user->pw_gid) != 0 || ::setuid(user->pw_uid) != 0) ::_exit(126);
      }
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // again: a change of user clears it
      if (::getppid() != test) ::_exit(127);
      const std::string port_text = std::to_string(port);
      const std::string socket_dir = dir.path.string();
      const std::string data_dir = data();
      ::execl(postgres_server, "postgres", "-D", data_dir.c_str(), "-p", port_text.c_str(), "-k", socket_dir.c_str(),
              "-c", "listen_addresses=127.0.0.1", "-c", durable_ ? "fsync=on" : "fsync=off", nullptr);
      ::_exit(127);
    }
    const std::string info = "host=" + dir.path.string() + " port=" + std::to_string(port) +
                             " dbname=postgres user=postgres connect_timeout=2";
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
      if (PQping(info.c_str()) == PQPING_OK) {
        running = true;
        return true;
      }
      if (rangekit::test::waited_within(server, std::chrono::milliseconds(50))) break;  // it ended
    }
    failure = "the server did not start: " + ls5_driver_test::read_file(dir.path / "server.log");
    stop();
    return false;
  }
  // As an outage: fast shutdown (SIGINT, as pg_ctl stop -m fast), every session ended.
  bool stop() {
    if (server > 0) {
      ::kill(server, SIGINT);
      if (!rangekit::test::waited_within(server, std::chrono::seconds(30))) rangekit::test::end_child(server);
    }
    server = -1;
    running = false;
    return true;
  }

  // Logins over TCP need the password from now on (scram-sha-256); the tests' own
  // connections come through the socket in the folder and stay trusted.
  bool require_password() {
    std::ofstream(dir.path / "data" / "pg_hba.conf", std::ios::trunc)
        << "local all all trust\nhost all all 127.0.0.1/32 scram-sha-256\n";
    return admin("postgres", "SELECT pg_reload_conf()");
  }

  // Runs SQL as the superuser over the socket; each row's columns as text (NULL: "\\N").
  [[nodiscard]] std::vector<std::vector<std::string>> query(const std::string& sql,
                                                            const std::string& database = "plant") const {
    std::vector<std::vector<std::string>> rows;
    PGconn* connection = connect(database);
    PGresult* result = PQexec(connection, sql.c_str());
    if (PQresultStatus(result) == PGRES_TUPLES_OK) {
      for (int row = 0; row < PQntuples(result); ++row) {
        auto& columns = rows.emplace_back();
        for (int column = 0; column < PQnfields(result); ++column) {
          columns.emplace_back(PQgetisnull(result, row, column) != 0 ? "\\N" : PQgetvalue(result, row, column));
        }
      }
    }
    PQclear(result);
    PQfinish(connection);
    return rows;
  }
  // The first column of the first row, or "" when there is none (or the query failed).
  [[nodiscard]] std::string value(const std::string& sql) const {
    const auto rows = query(sql);
    return rows.empty() || rows[0].empty() ? "" : rows[0][0];
  }
  // A statement without rows; false with the message in `failure` when it fails.
  bool admin(const std::string& database, const std::string& sql) {
    PGconn* connection = connect(database);
    PGresult* result = PQexec(connection, sql.c_str());
    const ExecStatusType status = PQresultStatus(result);
    const bool done = status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK;
    if (!done) failure = PQerrorMessage(connection);
    PQclear(result);
    PQfinish(connection);
    return done;
  }

  // Every seq of each sensor in `table`.
  [[nodiscard]] std::map<std::string, std::multiset<std::uint64_t>> sequences(
      const std::string& table = "readings") const {
    std::map<std::string, std::multiset<std::uint64_t>> found;
    for (const auto& row : query("SELECT sensor, seq FROM \"" + table + "\""))
      found[row[0]].insert(std::stoull(row[1]));
    return found;
  }

 private:
  bool durable_ = false;

  [[nodiscard]] PGconn* connect(const std::string& database) const {
    const std::string info = "host=" + dir.path.string() + " port=" + std::to_string(port) + " dbname=" + database +
                             " user=postgres connect_timeout=10";
    return PQconnectdb(info.c_str());
  }

 public:
  // One of the server's programs (initdb, psql) to its end (at most 60 s), as the
  // postgres user under root; its output in command.log.
  bool run(const std::vector<std::string>& arguments) {
    const std::string program = postgres_bin + arguments[0];
    std::vector<std::string> argv;
    if (::geteuid() == 0) argv = {"/usr/sbin/runuser", "-u", "postgres", "--"};
    argv.push_back(program);
    argv.insert(argv.end(), arguments.begin() + 1, arguments.end());
    const std::string log = (dir.path / "command.log").string();
    const pid_t pid = rangekit::test::fork_child();
    if (pid == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::chdir(dir.path.c_str());  // a folder the postgres user can read
      std::vector<char*> pointers;
      for (const std::string& each : argv) pointers.push_back(const_cast<char*>(each.c_str()));
      pointers.push_back(nullptr);
      ::execv(pointers[0], pointers.data());
      ::_exit(127);
    }
    const auto status = rangekit::test::waited_within(pid, std::chrono::seconds(60));
    if (!status) {
      rangekit::test::end_child(pid);
      return false;
    }
    return WIFEXITED(*status) && WEXITSTATUS(*status) == 0;
  }
};

}  // namespace sinks_test
