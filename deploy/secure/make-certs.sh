#!/usr/bin/env bash
# Makes a private CA and the router's TLS certificate for a gearcam shop network.
# Usage: make-certs.sh OUT_DIR [ROUTER_HOSTNAME]   (default hostname: localhost)
# Writes OUT_DIR/tls/{ca.pem,ca.key,router.pem,router.key}. Keep ca.key offline.
set -euo pipefail
out="${1:?usage: make-certs.sh OUT_DIR [ROUTER_HOSTNAME]}"
host="${2:-localhost}"
mkdir -p "$out/tls"
cd "$out/tls"
openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.pem -days 825 \
  -subj "/CN=gearcam shop CA" -addext "basicConstraints=critical,CA:TRUE" \
  -addext "keyUsage=critical,keyCertSign,cRLSign" 2>/dev/null
openssl req -newkey rsa:2048 -nodes -keyout router.key -out router.csr -subj "/CN=$host" 2>/dev/null
printf "subjectAltName=DNS:%s,DNS:localhost,IP:127.0.0.1\nbasicConstraints=CA:FALSE\nkeyUsage=digitalSignature,keyEncipherment\nextendedKeyUsage=serverAuth\n" "$host" > router.ext
openssl x509 -req -in router.csr -CA ca.pem -CAkey ca.key -CAcreateserial -out router.pem -days 825 \
  -extfile router.ext 2>/dev/null
rm -f router.csr router.ext ca.srl
chmod 600 ca.key router.key
echo "wrote $out/tls/ca.pem, router.pem, router.key (CA key: $out/tls/ca.key)"
