// The REST gateway's reference, rendered by swagger-ui (served from this
// folder, no CDN) from the server's own /openapi.json, so it always matches
// the server answering. "Try it out" calls this server.
window.ui = window.SwaggerUIBundle({
  url: '/openapi.json',
  dom_id: '#api',
  deepLinking: true,
  docExpansion: 'list',
});
