"""The addresses a browser on the local network can open, for the banner of ``rigid-body-lab``.

``--host 0.0.0.0`` listens on every interface, but nobody can open ``http://0.0.0.0``: the banner lists
this machine's own non-loopback IPv4 addresses instead (read from the host name's address records and
the network interfaces; no packet is sent anywhere).
"""

from __future__ import annotations

import ipaddress
import socket
import struct

__all__ = ["is_loopback", "lan_addresses", "urls"]


def is_loopback(host: str) -> bool:
    """True for 127.0.0.0/8, ::1 and ``localhost``."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


_SIOCGIFADDR = 0x8915  # Linux: the IPv4 address of a network interface


def _interface_addresses() -> set[str]:
    """IPv4 addresses of the network interfaces (Linux ioctl; elsewhere nothing, and the host name's
    records below are used). A datagram socket is opened to ask the kernel; nothing is sent."""
    found: set[str] = set()
    try:
        import fcntl

        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            for _, name in socket.if_nameindex():
                try:
                    packed = fcntl.ioctl(probe.fileno(), _SIOCGIFADDR, struct.pack("256s", name.encode()[:15]))
                except OSError:
                    continue  # an interface without an IPv4 address
                found.add(socket.inet_ntoa(packed[20:24]))
    except (ImportError, OSError):
        pass
    return found


def lan_addresses() -> list[str]:
    """This machine's non-loopback IPv4 addresses, sorted (empty when it has none)."""
    found: set[str] = _interface_addresses()
    names = {socket.gethostname(), socket.getfqdn()}
    for name in names:
        try:
            for info in socket.getaddrinfo(name, None, family=socket.AF_INET):
                found.add(str(info[4][0]))
        except OSError:
            continue
    return sorted(a for a in found if not ipaddress.ip_address(a).is_loopback)


def urls(host: str, port: int) -> list[str]:
    """The URLs to print for a server bound to ``host``: the host itself, or for an any-address bind
    (``0.0.0.0``, ``::``) every LAN address of this machine."""
    if host in ("0.0.0.0", "::", ""):
        return [f"http://{a}:{port}" for a in lan_addresses()]
    return [f"http://{host}:{port}"]
