#pragma once

// cmu-1990 Task Control Architecture: a tree of goals, commands and
// queries; a node may start only while its parent is active and after the
// node it is constrained to follow has finished. The executive grows it as
// the walk goes (a walk goal into step goals, each into its scan, plan,
// approval and moves) and the console shows it.

#include <functional>
#include <string>
#include <vector>

namespace ambler::executive {

enum class TaskKind { kGoal, kQuery, kApproval, kCommand };
enum class TaskStatus { kWaiting, kActive, kDone, kFailed, kSuspended };

std::string kindName(TaskKind kind);
std::string statusName(TaskStatus status);

struct Task {
  int id = 0;
  int parent = -1;  // -1: a root
  TaskKind kind = TaskKind::kGoal;
  std::string name;
  int after = -1;  // starts only once this task is done; -1: no constraint
  TaskStatus status = TaskStatus::kWaiting;
  double started_s = 0.0, ended_s = 0.0;
  std::string note;  // why it failed or was suspended
};

class TaskTree {
 public:
  int add(int parent, TaskKind kind, std::string name, int after = -1);
  // Parent active (or none) and the constraint met.
  bool canStart(int id) const;
  // Throws std::logic_error when the task cannot start or has ended.
  void start(int id, double now_s);
  void finish(int id, double now_s);
  void fail(int id, double now_s, const std::string& why);
  // Suspends the task and every active task under it.
  void suspend(int id, double now_s, const std::string& why);
  const Task& task(int id) const { return tasks_.at(std::size_t(id)); }
  const std::vector<Task>& tasks() const { return tasks_; }
  std::vector<int> children(int id) const;
  // Called with each task as it ends (done, failed or suspended): for the
  // mission log, so a replay can show when each module was busy.
  void onEnded(std::function<void(const Task&)> observer) { on_ended_ = std::move(observer); }

 private:
  Task& at(int id) { return tasks_.at(std::size_t(id)); }
  void end(int id, double now_s, TaskStatus status, const std::string& why);
  std::vector<Task> tasks_;
  std::function<void(const Task&)> on_ended_;
};

// The inverses of kindName and statusName; std::invalid_argument naming
// the text otherwise.
TaskKind kindFromName(const std::string& name);
TaskStatus statusFromName(const std::string& name);

}  // namespace ambler::executive
