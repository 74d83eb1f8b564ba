// Per-call workspaces for objects used from several threads at once. A call leases a workspace
// (a new one is made when every existing one is in use) and the lease gives it back when the
// call ends, so concurrent calls never share scratch memory and a steady state allocates nothing.
#pragma once
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

namespace hovi {

template <class W>
class WorkspacePool {
 public:
  explicit WorkspacePool(std::function<std::unique_ptr<W>()> make) : make_(std::move(make)) {}
  WorkspacePool(const WorkspacePool&) = delete;
  WorkspacePool& operator=(const WorkspacePool&) = delete;

  class Lease {
   public:
    Lease(WorkspacePool& pool, std::unique_ptr<W> w) : pool_(pool), w_(std::move(w)) {}
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() { pool_.give_back(std::move(w_)); }
    W& operator*() const { return *w_; }
    W* operator->() const { return w_.get(); }

   private:
    WorkspacePool& pool_;
    std::unique_ptr<W> w_;
  };

  Lease acquire() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<W> w = std::move(free_.back());
        free_.pop_back();
        return Lease(*this, std::move(w));
      }
    }
    return Lease(*this, make_());  // made outside the lock: construction may be slow
  }

 private:
  void give_back(std::unique_ptr<W> w) {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(w));
  }

  std::function<std::unique_ptr<W>()> make_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<W>> free_;
};

}  // namespace hovi
