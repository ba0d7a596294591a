// An LD_PRELOAD shim that keeps ROS on the loopback: a bind() to every interface (INADDR_ANY, the IPv6
// any address) becomes a bind to the loopback (127.0.0.1, ::1). roscpp's XML-RPC servers bind
// INADDR_ANY whatever ROS_IP says, so without it every node's XML-RPC port listens on every interface.
// scripts/ros_env.sh preloads it when it chooses the loopback (no ROS_IP or ROS_HOSTNAME of the user's);
// ROAR_BIND_ANY=1 turns it off. Binds to a particular address are left alone.
#include <dlfcn.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <cstdlib>
#include <cstring>

extern "C" int bind(int fd, const struct sockaddr* address, socklen_t length) {
  using Bind = int (*)(int, const struct sockaddr*, socklen_t);
  static const Bind real_bind = reinterpret_cast<Bind>(dlsym(RTLD_NEXT, "bind"));
  static const bool any_allowed = [] {
    const char* v = std::getenv("ROAR_BIND_ANY");
    return v && std::strcmp(v, "1") == 0;
  }();
  if (!any_allowed && address && address->sa_family == AF_INET && length >= sizeof(sockaddr_in)) {
    sockaddr_in in;
    std::memcpy(&in, address, sizeof in);
    if (in.sin_addr.s_addr == htonl(INADDR_ANY)) {
      in.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      return real_bind(fd, reinterpret_cast<const sockaddr*>(&in), sizeof in);
    }
  } else if (!any_allowed && address && address->sa_family == AF_INET6 && length >= sizeof(sockaddr_in6)) {
    sockaddr_in6 in6;
    std::memcpy(&in6, address, sizeof in6);
    if (std::memcmp(&in6.sin6_addr, &in6addr_any, sizeof in6addr_any) == 0) {
      in6.sin6_addr = in6addr_loopback;
      return real_bind(fd, reinterpret_cast<const sockaddr*>(&in6), sizeof in6);
    }
  }
  return real_bind(fd, address, length);
}
