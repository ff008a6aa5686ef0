#include "executive/TaskTree.h"

#include <stdexcept>

namespace ambler::executive {

std::string kindName(TaskKind kind) {
  switch (kind) {
    case TaskKind::kGoal:
      return "goal";
    case TaskKind::kQuery:
      return "query";
    case TaskKind::kApproval:
      return "approval";
    case TaskKind::kCommand:
      return "command";
  }
  return "?";
}

std::string statusName(TaskStatus status) {
  switch (status) {
    case TaskStatus::kWaiting:
      return "waiting";
    case TaskStatus::kActive:
      return "active";
    case TaskStatus::kDone:
      return "done";
    case TaskStatus::kFailed:
      return "failed";
    case TaskStatus::kSuspended:
      return "suspended";
  }
  return "?";
}

int TaskTree::add(int parent, TaskKind kind, std::string name, int after) {
  if (parent >= int(tasks_.size()) || after >= int(tasks_.size()))
    throw std::logic_error("task '" + name + "' refers to a task that does not exist");
  Task t;
  t.id = int(tasks_.size());
  t.parent = parent;
  t.kind = kind;
  t.name = std::move(name);
  t.after = after;
  tasks_.push_back(std::move(t));
  return tasks_.back().id;
}

bool TaskTree::canStart(int id) const {
  const Task& t = task(id);
  if (t.status != TaskStatus::kWaiting) return false;
  if (t.parent >= 0 && task(t.parent).status != TaskStatus::kActive) return false;
  return t.after < 0 || task(t.after).status == TaskStatus::kDone;
}

void TaskTree::start(int id, double now_s) {
  if (!canStart(id))
    throw std::logic_error("task '" + task(id).name + "' cannot start: it is " +
                           statusName(task(id).status) +
                           ", or its parent or predecessor is not ready");
  at(id).status = TaskStatus::kActive;
  at(id).started_s = now_s;
}

void TaskTree::end(int id, double now_s, TaskStatus status, const std::string& why) {
  Task& t = at(id);
  if (t.status != TaskStatus::kActive && t.status != TaskStatus::kWaiting)
    throw std::logic_error("task '" + t.name + "' has already ended (" + statusName(t.status) +
                           ")");
  t.status = status;
  t.ended_s = now_s;
  t.note = why;
  if (on_ended_) on_ended_(t);
}

void TaskTree::finish(int id, double now_s) { end(id, now_s, TaskStatus::kDone, {}); }

void TaskTree::fail(int id, double now_s, const std::string& why) {
  end(id, now_s, TaskStatus::kFailed, why);
}

void TaskTree::suspend(int id, double now_s, const std::string& why) {
  for (int child : children(id))
    if (task(child).status == TaskStatus::kActive) suspend(child, now_s, why);
  end(id, now_s, TaskStatus::kSuspended, why);
}

std::vector<int> TaskTree::children(int id) const {
  std::vector<int> out;
  for (const auto& t : tasks_)
    if (t.parent == id) out.push_back(t.id);
  return out;
}

TaskKind kindFromName(const std::string& name) {
  for (auto k : {TaskKind::kGoal, TaskKind::kQuery, TaskKind::kApproval, TaskKind::kCommand})
    if (kindName(k) == name) return k;
  throw std::invalid_argument("unknown task kind \"" + name + "\"");
}

TaskStatus statusFromName(const std::string& name) {
  for (auto s : {TaskStatus::kWaiting, TaskStatus::kActive, TaskStatus::kDone, TaskStatus::kFailed,
                 TaskStatus::kSuspended})
    if (statusName(s) == name) return s;
  throw std::invalid_argument("unknown task status \"" + name + "\"");
}

}  // namespace ambler::executive
