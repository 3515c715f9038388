// A real PostgreSQL 15 cluster (Debian's postgresql-15) in a temp folder, on a free loopback
// port, for the postgres sink's tests: initdb'd and started by the test, stopped and removed
// with it. As root it runs as the `postgres` user (runuser); otherwise as the test's own.
#pragma once

#include <libpq-fe.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
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

struct PostgresCluster {
  ls5_driver_test::TempDir dir;
  std::uint16_t port = free_port();
  bool running = false;
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

  bool start() {
    const std::string options = "-p " + std::to_string(port) + " -k " + dir.path.string() +
                                " -c listen_addresses=127.0.0.1" + (durable_ ? "" : " -c fsync=off");
    running = run(
        {"pg_ctl", "-D", data(), "-l", (dir.path / "server.log").string(), "-o", options, "-w", "-t", "30", "start"});
    if (!running) failure = "pg_ctl start failed: " + ls5_driver_test::read_file(dir.path / "server.log");
    return running;
  }
  // As an outage: fast shutdown, every session ended.
  bool stop() {
    if (!running) return true;
    running = !run({"pg_ctl", "-D", data(), "-m", "fast", "-w", "-t", "30", "stop"});
    return !running;
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
  // One of the server's programs (initdb, pg_ctl, psql) to its end (at most 60 s), as the
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
